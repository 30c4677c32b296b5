// The ES variation and selection of seed 004 (evolution_strategy.h), on model/random.h's draws
// so that a seed means the same run on every compiler.
#include "csgfit/search/evolution_strategy.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "model/random.h"

namespace csgfit::es {

static_assert(std::is_same_v<Rng, rnd::Rng>, "the ES draws from the searches' generator");

namespace {

double key(const Individual& i) {
  return std::isnan(i.fitness) ? std::numeric_limits<double>::infinity() : i.fitness;
}

void recombine_into(std::vector<double>& out, const std::vector<double>& a,
                    const std::vector<double>& b, Recombination how, Rng& rng) {
  out = a;
  if (how == Recombination::None) return;
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = how == Recombination::Intermediate ? 0.5 * (a[i] + b[i])
                                                 : (rng() & 1 ? b[i] : a[i]);
}

void clamp_into_box(std::vector<double>& x, const StrategyParams& params) {
  for (std::size_t i = 0; i < x.size() && !params.lower.empty(); ++i)
    x[i] = std::clamp(x[i], params.lower[i], params.upper[i]);
}

void check(const StrategyParams& params, const std::vector<Individual>& first) {
  const auto bad = [](const char* why) { throw std::invalid_argument(std::string("ES: ") + why); };
  if (params.mu == 0 || params.lambda == 0) bad("mu and lambda must be at least 1");
  if (params.selection == Selection::Comma && params.lambda < params.mu)
    bad("(mu, lambda) needs lambda >= mu");
  if (first.empty()) bad("no start individual");
  const std::size_t n = first[0].x.size();
  for (const Individual& i : first)
    if (i.x.size() != n || (i.sigma.size() != 1 && i.sigma.size() != n) ||
        i.sigma.size() != first[0].sigma.size())
      bad("start individuals differ in size, or a step size count is neither 1 nor n");
  if (params.lower.size() != params.upper.size() || (!params.lower.empty() && params.lower.size() != n))
    bad("the box needs one lower and one upper bound per parameter");
  for (std::size_t i = 0; i < params.lower.size(); ++i)
    if (!(params.lower[i] <= params.upper[i])) bad("a lower bound above its upper bound");
}

}  // namespace

StepRule StepRule::standard(std::size_t n, std::size_t steps, double min_step) {
  const double d = static_cast<double>(std::max<std::size_t>(n, 1));
  if (steps == 1) return {1 / std::sqrt(d), 0.0, min_step};
  return {1 / std::sqrt(2 * d), 1 / std::sqrt(2 * std::sqrt(d)), min_step};
}

void mutate(std::vector<double>& x, std::vector<double>& sigma, const StepRule& rule, Rng& rng) {
  if (sigma.size() != 1 && sigma.size() != x.size())
    throw std::invalid_argument("ES: need one step size or one per parameter");
  const double common = rule.tau0 * rnd::normal(rng, 0, 1);
  for (double& s : sigma)
    s = std::max(rule.min_step, s * std::exp(common + rule.tau * rnd::normal(rng, 0, 1)));
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += sigma[sigma.size() == 1 ? 0 : i] * rnd::normal(rng, 0, 1);
}

Individual recombine(const Individual& a, const Individual& b, Recombination parameters,
                     Recombination step_sizes, Rng& rng) {
  Individual child;
  recombine_into(child.x, a.x, b.x, parameters, rng);
  recombine_into(child.sigma, a.sigma, b.sigma, step_sizes, rng);
  return child;
}

std::vector<Individual> make_offspring(const std::vector<Individual>& parents,
                                       const StrategyParams& params, const StepRule& rule,
                                       Rng& rng) {
  std::vector<Individual> offspring;
  offspring.reserve(params.lambda);
  for (std::size_t k = 0; k < params.lambda; ++k) {
    const Individual& a = parents[rnd::pick(rng, parents.size())];
    const Individual& b = parents[rnd::pick(rng, parents.size())];
    offspring.push_back(recombine(a, b, params.parameters, params.step_sizes, rng));
    mutate(offspring.back().x, offspring.back().sigma, rule, rng);
    clamp_into_box(offspring.back().x, params);
  }
  return offspring;
}

void select(std::vector<Individual>& parents, std::vector<Individual> offspring,
            Selection selection, std::size_t mu) {
  std::vector<Individual> pool;
  if (selection == Selection::Plus) pool = std::move(parents);
  pool.insert(pool.end(), std::make_move_iterator(offspring.begin()),
              std::make_move_iterator(offspring.end()));
  std::stable_sort(pool.begin(), pool.end(),
                   [](const Individual& a, const Individual& b) { return key(a) < key(b); });
  pool.resize(std::min(pool.size(), mu));
  parents = std::move(pool);
}

EvolutionStrategy::EvolutionStrategy(StrategyParams params, std::vector<Individual> first,
                                     std::uint64_t seed)
    : params_(std::move(params)), parents_(std::move(first)), rng_(rnd::splitmix(seed)) {
  check(params_, parents_);
  rule_ = StepRule::standard(parents_[0].x.size(), parents_[0].sigma.size(), params_.min_step);
}

void EvolutionStrategy::start() {
  evaluated_ = true;
  select(parents_, {}, Selection::Plus, params_.mu);
  remember_best();
}

void EvolutionStrategy::remember_best() {
  if (key(parents_[0]) < key(best_)) best_ = parents_[0];
}

}  // namespace csgfit::es
