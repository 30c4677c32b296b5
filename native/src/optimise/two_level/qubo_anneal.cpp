// Simulated annealing of the seed's set-cover QUBO, standing in for the D-Wave annealer.
#include <algorithm>
#include <cmath>
#include <random>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace {

constexpr double kPenalty = 2.0;  // A > B = 1: breaking a constraint never pays for a subset
constexpr double kStartTemperature = 3.0, kEndTemperature = 0.02;

// The QUBO as local fields: flipping x_i changes the energy by (1 - 2 x_i) * field_i.
class Annealer {
 public:
  Annealer(const SetCoverInstance& instance, std::uint64_t seed)
      : instance_(instance), rng_(seed), x_(qubo_assignment(instance, {})),
        count_vars_(instance.universe) {
    const Qubo q = set_cover_qubo_matrix(instance, kPenalty, 1.0);
    field_.assign(q.n, 0.0);
    neighbours_.resize(q.n);
    for (const auto& [i, j, w] : q.terms) {
      if (i == j) field_[i] += w;
      else neighbours_[i].emplace_back(j, w), neighbours_[j].emplace_back(i, w);
    }
    std::vector<std::size_t> containing(instance.universe, 0);
    for (const auto& subset : instance.subsets)
      for (std::size_t e : subset) ++containing[e];
    for (std::size_t v = instance.subsets.size(), a = 0; a < instance.universe; ++a)
      for (std::size_t m = 0; m < containing[a]; ++m) count_vars_[a].push_back(v++);
    times_.assign(instance.universe, 0);
    energy_ = best_energy_ = q.offset;
    best_ = x_;
  }

  std::vector<std::size_t> run(std::size_t sweeps) {
    const double ratio = std::pow(kEndTemperature / kStartTemperature,
                                  1.0 / static_cast<double>(std::max<std::size_t>(sweeps, 2) - 1));
    double temperature = kStartTemperature;
    for (std::size_t sweep = 0; sweep < sweeps; ++sweep, temperature *= ratio) {
      for (std::size_t k = 0; k < instance_.subsets.size(); ++k) subset_move(temperature);
      for (std::size_t k = 0; k <= x_.size() / 8; ++k) bit_move(temperature);
    }
    std::vector<std::size_t> chosen;
    for (std::size_t s = 0; s < instance_.subsets.size(); ++s)
      if (best_[s]) chosen.push_back(s);
    return chosen;
  }

 private:
  double flip(std::size_t i) {
    const double delta = (x_[i] ? -1.0 : 1.0) * field_[i];
    const double sign = x_[i] ? -1.0 : 1.0;
    x_[i] ^= 1;
    for (const auto& [j, w] : neighbours_[i]) field_[j] += sign * w;
    return delta;
  }

  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

  // Metropolis on a list of flips, undone if refused.
  void attempt(const std::vector<std::size_t>& flips, double temperature) {
    double delta = 0.0;
    for (std::size_t i : flips) delta += flip(i);
    if (delta > 0 && uniform() >= std::exp(-delta / temperature)) {
      for (auto it = flips.rbegin(); it != flips.rend(); ++it) flip(*it);
      return;
    }
    energy_ += delta;
    if (energy_ < best_energy_ - 1e-9) best_energy_ = energy_, best_ = x_;
  }

  // Single flips alone rarely pass the penalty walls between covers, so the main move takes
  // or drops a subset together with the counts of its elements (the one-hot made consistent).
  void subset_move(double temperature) {
    const std::size_t s = static_cast<std::size_t>(rng_() % instance_.subsets.size());
    std::vector<std::size_t> flips{s};
    const std::size_t step = x_[s] ? std::size_t(-1) : 1;
    for (std::size_t a : instance_.subsets[s]) {
      const std::size_t target = times_[a] + step;
      for (std::size_t m = 0; m < count_vars_[a].size(); ++m)
        if (x_[count_vars_[a][m]] != (m + 1 == target ? 1 : 0)) flips.push_back(count_vars_[a][m]);
    }
    const std::uint8_t before = x_[s];
    attempt(flips, temperature);
    if (x_[s] != before)
      for (std::size_t a : instance_.subsets[s]) times_[a] += step;
  }

  void bit_move(double temperature) {
    const std::size_t i = static_cast<std::size_t>(rng_() % x_.size());
    if (i < instance_.subsets.size()) return;  // subsets move with their counts
    attempt({i}, temperature);
  }

  const SetCoverInstance& instance_;
  std::mt19937_64 rng_;
  std::vector<std::uint8_t> x_, best_;
  std::vector<double> field_;
  std::vector<std::vector<std::pair<std::size_t, double>>> neighbours_;
  std::vector<std::vector<std::size_t>> count_vars_;
  std::vector<std::size_t> times_;  // how many taken subsets hold each element
  double energy_ = 0.0, best_energy_ = 0.0;
};

}  // namespace

SetCoverResult set_cover_qubo(const SetCoverInstance& instance, std::uint64_t seed,
                              std::size_t sweeps) {
  if (instance.universe == 0) return {};
  std::vector<std::size_t> chosen =
      instance.subsets.empty() ? std::vector<std::size_t>{} : Annealer(instance, seed).run(sweeps);
  chosen = detail::greedy_cover(instance, std::move(chosen));
  detail::drop_redundant(instance, chosen);
  std::sort(chosen.begin(), chosen.end());
  return {chosen, false};
}

}  // namespace csgfit::two_level
