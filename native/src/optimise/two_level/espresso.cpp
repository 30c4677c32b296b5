// Espresso-style minimisation (Brayton et al. 1984) against an explicit off-set: EXPAND,
// IRREDUNDANT and REDUCE until the cost stops falling.
#include <algorithm>
#include <numeric>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace {



// Literal order for EXPAND: first the literals that keep the most uncovered on-minterms out,
// each minterm counted 1/k over its k conflicting literals, so near minterms weigh most.
std::vector<std::size_t> expand_order(const Cube& cube, const TruthTable& t,
                                      const std::vector<bool>& covered) {
  std::vector<double> weight(t.variables, 0.0);
  BitRow conflict(cube.care.size());
  for (std::size_t k = 0; k < t.on.size(); ++k) {
    if (covered[k]) continue;
    for (std::size_t w = 0; w < conflict.size(); ++w)
      conflict[w] = (t.on[k][w] ^ cube.value[w]) & cube.care[w];
    const std::size_t count = detail::popcount(conflict);
    if (count == 0) continue;
    for (std::size_t i = 0; i < t.variables; ++i)
      if (detail::test_bit(conflict, i)) weight[i] += 1.0 / static_cast<double>(count);
  }
  std::vector<std::size_t> order(t.variables);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return weight[a] > weight[b]; });
  return order;
}

void mark_covered(const Cube& cube, const TruthTable& t, std::vector<bool>& covered) {
  for (std::size_t k = 0; k < t.on.size(); ++k)
    if (!covered[k] && cube.contains(t.on[k])) covered[k] = true;
}

// EXPAND: each cube, largest first, grows to a prime; cubes inside an earlier prime go.
Cover expand_all(Cover cover, const TruthTable& t) {
  std::stable_sort(cover.begin(), cover.end(), [](const Cube& a, const Cube& b) {
    return a.literal_count() < b.literal_count();
  });
  Cover primes;
  std::vector<bool> covered(t.on.size(), false);
  for (const Cube& cube : cover) {
    if (std::any_of(primes.begin(), primes.end(),
                    [&](const Cube& p) { return detail::cube_contains(p, cube); }))
      continue;
    primes.push_back(detail::expand(cube, t.off, expand_order(cube, t, covered)));
    mark_covered(primes.back(), t, covered);
  }
  return primes;
}

// IRREDUNDANT: with the on-set explicit this is dropping redundant subsets of a set cover.
Cover irredundant(const Cover& cover, const TruthTable& t) {
  const SetCoverInstance instance = cover_instance(t.on, cover);
  std::vector<std::size_t> chosen(cover.size());
  std::iota(chosen.begin(), chosen.end(), std::size_t{0});
  detail::drop_redundant(instance, chosen);
  std::sort(chosen.begin(), chosen.end());
  Cover out;
  for (std::size_t i : chosen) out.push_back(cover[i]);
  return out;
}

// REDUCE: each cube, largest first, shrinks to the supercube of the on-minterms only it
// covers, so that the next EXPAND can grow it in another direction.
Cover reduce(Cover cover, const TruthTable& t) {
  std::vector<std::size_t> times(t.on.size(), 0);
  for (const Cube& cube : cover)
    for (std::size_t k = 0; k < t.on.size(); ++k) times[k] += cube.contains(t.on[k]) ? 1 : 0;
  Cover out;
  for (Cube& cube : cover) {
    std::vector<BitRow> own;
    for (std::size_t k = 0; k < t.on.size(); ++k)
      if (cube.contains(t.on[k]) && times[k] == 1) own.push_back(t.on[k]);
    for (std::size_t k = 0; k < t.on.size(); ++k)
      if (cube.contains(t.on[k])) --times[k];
    if (own.empty()) continue;
    Cube reduced = detail::supercube(own, t.variables);
    for (std::size_t k = 0; k < t.on.size(); ++k) times[k] += reduced.contains(t.on[k]) ? 1 : 0;
    out.push_back(std::move(reduced));
  }
  return out;
}

}  // namespace

Cover espresso(const TruthTable& table) {
  const TruthTable t = deduplicated(table);
  Cover cover;
  for (const BitRow& m : t.on) cover.push_back(detail::minterm_cube(m, t.variables));
  cover = irredundant(expand_all(std::move(cover), t), t);
  Cover best = cover;
  for (;;) {
    cover = irredundant(expand_all(reduce(cover, t), t), t);
    if (!(detail::cost_of(cover) < detail::cost_of(best))) break;
    best = cover;
  }
  return best;
}

}  // namespace csgfit::two_level
