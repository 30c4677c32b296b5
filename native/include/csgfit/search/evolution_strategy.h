// Seed 004's evolution strategy (Sec. 2.5.1 "Terminal", Sec. 3; Schwefel 1995) over real
// parameter vectors: every individual carries its own step sizes, self-adapted by the
// log-normal rule, and the population is selected (mu, lambda) or (mu + lambda). The variation
// (mutate, recombine) is free-standing so that the GP over CSG trees can apply the same
// terminal mutation to one primitive's parameters; EvolutionStrategy is the plain ES loop over
// any fitness function, lower is better (as score() is; negate a fitness to be maximised).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace csgfit::es {

/// The generator every search draws from (model/random.h's rnd::Rng, the same type).
using Rng = std::mt19937_64;

/// (mu, lambda): the mu best of the lambda offspring; (mu + lambda): of parents and offspring.
enum class Selection { Comma, Plus };
/// How two parents make one offspring: a copy of one, each coordinate from either (discrete),
/// or their mean (intermediate).
enum class Recombination { None, Discrete, Intermediate };

/// The log-normal self-adaptation sigma_i' = max(min_step, sigma_i exp(tau0 N(0,1) + tau N_i(0,1)))
/// with N(0,1) drawn once per individual and N_i(0,1) once per step size.
struct StepRule {
  double tau0 = 0, tau = 0;
  /// Step sizes never fall below it: a sigma of 0 could never grow again.
  double min_step = 1e-12;
  /// Schwefel's rates for n parameters: with n step sizes tau0 = 1/sqrt(2n) (the common
  /// factor) and tau = 1/sqrt(2 sqrt(n)); with one step size tau0 = 1/sqrt(n), tau = 0.
  static StepRule standard(std::size_t n, std::size_t steps, double min_step = 1e-12);
};

/// A parameter vector with its own step sizes: one per parameter, or one for all of them (the
/// seed's "single step size of each CSG object").
struct Individual {
  std::vector<double> x, sigma;
  double fitness = std::numeric_limits<double>::infinity();
};

struct StrategyParams {
  std::size_t mu = 15, lambda = 100;
  Selection selection = Selection::Comma;
  /// Schwefel's usual choice: discrete for the parameters, intermediate for the step sizes.
  Recombination parameters = Recombination::Discrete;
  Recombination step_sizes = Recombination::Intermediate;
  double min_step = 1e-12;
  /// Optional box (empty, or one bound per parameter): a mutated parameter is clamped into it.
  std::vector<double> lower, upper;
};

/// Mutates in place: first the step sizes by `rule`, then x_i += sigma_i' N(0, 1) (sigma of
/// size 1 serves every parameter). Throws std::invalid_argument when sigma has neither one nor
/// x.size() entries.
void mutate(std::vector<double>& x, std::vector<double>& sigma, const StepRule& rule, Rng& rng);
/// One offspring of a and b (same sizes), parameters and step sizes recombined separately.
Individual recombine(const Individual& a, const Individual& b, Recombination parameters,
                     Recombination step_sizes, Rng& rng);
/// lambda unevaluated offspring: each of two parents drawn uniformly, recombined, mutated,
/// clamped into the box.
std::vector<Individual> make_offspring(const std::vector<Individual>& parents,
                                       const StrategyParams& params, const StepRule& rule,
                                       Rng& rng);
/// The next parents, best first (NaN counts as worst; ties keep the earlier, parents first
/// under Plus, so that (mu + lambda) never replaces a parent by an equal offspring).
void select(std::vector<Individual>& parents, std::vector<Individual> offspring,
            Selection selection, std::size_t mu);

/// When run() stops: after max_generations, or once the best fitness is <= target.
struct StopRule {
  std::size_t max_generations = 1000;
  double target = -std::numeric_limits<double>::infinity();
};

/// The ES loop. Deterministic for a seed: one generator, offspring evaluated in order.
class EvolutionStrategy {
 public:
  /// `first`: one or more individuals of the same sizes (fitness need not be set; they are
  /// evaluated by the first step). Throws std::invalid_argument on sizes or counts that do not
  /// fit (mu or lambda 0, lambda < mu under Comma, a box of the wrong size).
  EvolutionStrategy(StrategyParams params, std::vector<Individual> first, std::uint64_t seed);

  /// One generation: lambda offspring, evaluated by fitness(const std::vector<double>&), selected.
  template <class Fitness>
  void step(Fitness&& fitness) {
    if (!evaluated_) {
      evaluate(parents_, fitness);
      start();
    }
    std::vector<Individual> offspring = make_offspring(parents_, params_, rule_, rng_);
    evaluate(offspring, fitness);
    select(parents_, std::move(offspring), params_.selection, params_.mu);
    ++generation_;
    remember_best();
  }

  /// Steps until `stop`; returns the best individual seen.
  template <class Fitness>
  const Individual& run(Fitness&& fitness, const StopRule& stop) {
    while (generation_ < stop.max_generations && !(best_.fitness <= stop.target)) step(fitness);
    return best_;
  }

  const std::vector<Individual>& parents() const { return parents_; }
  /// The best individual ever evaluated (under Comma the parents may have lost it).
  const Individual& best() const { return best_; }
  std::size_t generation() const { return generation_; }
  const StepRule& rule() const { return rule_; }

 private:
  template <class Fitness>
  static void evaluate(std::vector<Individual>& group, Fitness& fitness) {
    for (Individual& i : group) i.fitness = fitness(static_cast<const std::vector<double>&>(i.x));
  }
  /// After the start is evaluated: sorted, cut to mu, its best remembered.
  void start();
  void remember_best();

  StrategyParams params_;
  StepRule rule_;
  std::vector<Individual> parents_;
  Individual best_;
  Rng rng_;
  std::size_t generation_ = 0;
  bool evaluated_ = false;
};

}  // namespace csgfit::es
