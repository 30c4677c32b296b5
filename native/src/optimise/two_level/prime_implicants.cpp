// The seed's prime implicants "by the definition" (Sec. 5.3.1), and their selection by set
// cover.
#include <algorithm>
#include <numeric>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace {

// Different drop orders reach different primes from one minterm; four cheap ones: forwards,
// backwards, and both started from the middle variable.
std::vector<std::vector<std::size_t>> drop_orders(std::size_t variables) {
  std::vector<std::size_t> forward(variables);
  std::iota(forward.begin(), forward.end(), std::size_t{0});
  std::vector<std::size_t> rotated = forward;
  std::rotate(rotated.begin(), rotated.begin() + static_cast<std::ptrdiff_t>(variables / 2),
              rotated.end());
  std::vector<std::vector<std::size_t>> orders{forward, forward, rotated, rotated};
  std::reverse(orders[1].begin(), orders[1].end());
  std::reverse(orders[3].begin(), orders[3].end());
  return orders;
}

bool cube_less(const Cube& a, const Cube& b) {
  return a.care != b.care ? a.care < b.care : a.value < b.value;
}

}  // namespace

std::vector<Cube> prime_implicants(const TruthTable& table) {
  const TruthTable t = deduplicated(table);
  const auto orders = drop_orders(t.variables);
  std::vector<Cube> primes;
  for (const BitRow& m : t.on)
    for (const auto& order : orders)
      primes.push_back(detail::expand(detail::minterm_cube(m, t.variables), t.off, order));
  std::sort(primes.begin(), primes.end(), cube_less);
  primes.erase(std::unique(primes.begin(), primes.end()), primes.end());
  return primes;
}

Cover set_cover_minimise(const TruthTable& table, bool exact, std::uint64_t seed) {
  const TruthTable t = deduplicated(table);
  const std::vector<Cube> primes = prime_implicants(t);
  const SetCoverInstance instance = cover_instance(t.on, primes);
  const SetCoverResult result = exact ? set_cover_exact(instance) : set_cover_qubo(instance, seed);
  Cover cover;
  for (std::size_t i : result.chosen) cover.push_back(primes[i]);
  return cover;
}

}  // namespace csgfit::two_level
