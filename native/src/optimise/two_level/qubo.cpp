// The seed's Eq. 3: Lucas's (2014) QUBO for set cover.
#include <algorithm>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace {

// Index of x_{a,1} for every element a: the counts follow the subset variables.
std::vector<std::size_t> count_bases(const SetCoverInstance& instance,
                                     std::vector<std::size_t>& containing) {
  containing.assign(instance.universe, 0);
  for (const auto& subset : instance.subsets)
    for (std::size_t e : subset) ++containing[e];
  std::vector<std::size_t> bases(instance.universe);
  std::size_t next = instance.subsets.size();
  for (std::size_t a = 0; a < instance.universe; ++a) bases[a] = next, next += containing[a];
  return bases;
}

}  // namespace

double Qubo::energy(const std::vector<std::uint8_t>& x) const {
  double e = offset;
  for (const auto& [i, j, w] : terms)
    if (x[i] && x[j]) e += w;
  return e;
}

Qubo set_cover_qubo_matrix(const SetCoverInstance& instance, double A, double B) {
  std::vector<std::size_t> containing;
  const std::vector<std::size_t> bases = count_bases(instance, containing);
  std::vector<std::vector<std::size_t>> holders(instance.universe);
  for (std::size_t s = 0; s < instance.subsets.size(); ++s)
    for (std::size_t e : instance.subsets[s]) holders[e].push_back(s);
  Qubo q;
  q.n = instance.subsets.size();
  for (std::size_t s = 0; s < instance.subsets.size(); ++s) q.terms.emplace_back(s, s, B);
  for (std::size_t a = 0; a < instance.universe; ++a) {
    q.n += containing[a];
    q.offset += A;  // (1 - sum_m y_m)^2 with every y_m = 0
    for (std::size_t m = 1; m <= containing[a]; ++m) {
      const std::size_t ym = bases[a] + m - 1;
      const double dm = static_cast<double>(m);
      q.terms.emplace_back(ym, ym, -A + A * dm * dm);
      for (std::size_t k = m + 1; k <= containing[a]; ++k)
        q.terms.emplace_back(ym, bases[a] + k - 1, 2 * A + 2 * A * dm * static_cast<double>(k));
      for (std::size_t s : holders[a]) q.terms.emplace_back(std::min(s, ym), std::max(s, ym), -2 * A * dm);
    }
    for (std::size_t i = 0; i < holders[a].size(); ++i) {
      q.terms.emplace_back(holders[a][i], holders[a][i], A);
      for (std::size_t j = i + 1; j < holders[a].size(); ++j)
        q.terms.emplace_back(holders[a][i], holders[a][j], 2 * A);
    }
  }
  return q;
}

std::vector<std::uint8_t> qubo_assignment(const SetCoverInstance& instance,
                                          const std::vector<std::size_t>& chosen) {
  std::vector<std::size_t> containing;
  const std::vector<std::size_t> bases = count_bases(instance, containing);
  std::vector<std::uint8_t> x(instance.subsets.size(), 0);
  x.resize(instance.universe == 0 ? x.size() : bases.back() + containing.back(), 0);
  std::vector<std::size_t> times(instance.universe, 0);
  for (std::size_t s : chosen) {
    x[s] = 1;
    for (std::size_t e : instance.subsets[s]) ++times[e];
  }
  for (std::size_t a = 0; a < instance.universe; ++a)
    if (times[a] > 0) x[bases[a] + times[a] - 1] = 1;
  return x;
}

}  // namespace csgfit::two_level
