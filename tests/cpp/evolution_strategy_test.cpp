// Seed 004's ES: log-normal self-adaptation, (mu, lambda) and (mu + lambda), recombination.
#include "csgfit/search/evolution_strategy.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

using namespace csgfit::es;

namespace {

double sphere(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v * v;
  return s;
}

// Rastrigin: many local minima, so a (mu + lambda) run keeps meeting worse offspring.
double rastrigin(const std::vector<double>& x) {
  double s = 10.0 * static_cast<double>(x.size());
  for (double v : x) s += v * v - 10 * std::cos(2 * 3.14159265358979323846 * v);
  return s;
}

Individual start_point(std::size_t n, std::size_t steps, double value = 3.0) {
  return {std::vector<double>(n, value), std::vector<double>(steps, 1.0)};
}

double median_step(const std::vector<Individual>& parents) {
  std::vector<double> s;
  for (const Individual& i : parents) s.insert(s.end(), i.sigma.begin(), i.sigma.end());
  std::nth_element(s.begin(), s.begin() + static_cast<long>(s.size() / 2), s.end());
  return s[s.size() / 2];
}

}  // namespace

TEST(EvolutionStrategy, StandardRates) {
  const StepRule n = StepRule::standard(10, 10);
  EXPECT_DOUBLE_EQ(n.tau0, 1 / std::sqrt(20.0));
  EXPECT_DOUBLE_EQ(n.tau, 1 / std::sqrt(2 * std::sqrt(10.0)));
  const StepRule one = StepRule::standard(10, 1);
  EXPECT_DOUBLE_EQ(one.tau0, 1 / std::sqrt(10.0));
  EXPECT_EQ(one.tau, 0.0);
}

TEST(EvolutionStrategy, CommaConvergesOnTheSphereAndStepSizesShrink) {
  for (std::size_t steps : {std::size_t{10}, std::size_t{1}}) {
    EvolutionStrategy es(StrategyParams{}, {start_point(10, steps)}, 1);
    es.step(sphere);
    const double first_step = median_step(es.parents());
    const Individual& best = es.run(sphere, StopRule{300, 1e-6});
    EXPECT_LE(best.fitness, 1e-6) << steps << " step sizes";
    EXPECT_LT(es.generation(), 300u);  // about 50 (one step size) to 90 (ten) at seeds 1-5
    EXPECT_LT(median_step(es.parents()), 1e-2 * first_step);
    EXPECT_EQ(sphere(best.x), best.fitness);
  }
}

TEST(EvolutionStrategy, SameSeedSameRun) {
  const auto run = [](std::uint64_t seed) {
    EvolutionStrategy es(StrategyParams{}, {start_point(10, 10)}, seed);
    es.run(sphere, StopRule{60});
    return es.parents();
  };
  const std::vector<Individual> a = run(7), b = run(7), c = run(8);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].x, b[k].x);
    EXPECT_EQ(a[k].sigma, b[k].sigma);
    EXPECT_EQ(a[k].fitness, b[k].fitness);
  }
  EXPECT_NE(a[0].x, c[0].x);
}

// Under (mu + lambda) the k-th best parent can only improve: the old parents compete too.
TEST(EvolutionStrategy, PlusNeverGetsWorse) {
  StrategyParams params;
  params.mu = 5;
  params.lambda = 20;
  params.selection = Selection::Plus;
  EvolutionStrategy es(params, {start_point(6, 6, 2.5), start_point(6, 6, -1.5)}, 3);
  es.step(rastrigin);
  std::vector<double> last;
  for (const Individual& i : es.parents()) last.push_back(i.fitness);
  for (int g = 0; g < 300; ++g) {
    es.step(rastrigin);
    ASSERT_EQ(es.parents().size(), last.size());
    for (std::size_t k = 0; k < last.size(); ++k) {
      EXPECT_LE(es.parents()[k].fitness, last[k]) << "generation " << g << " rank " << k;
      last[k] = es.parents()[k].fitness;
    }
  }
  EXPECT_EQ(es.best().fitness, es.parents()[0].fitness);
}

TEST(EvolutionStrategy, MutationKeepsTheLowerBoundOnStepSizes) {
  Rng rng(1);
  std::vector<double> x(4, 0.0), sigma(4, 1e-300);
  const StepRule rule = StepRule::standard(4, 4, 1e-9);
  for (int k = 0; k < 100; ++k) {
    mutate(x, sigma, rule, rng);
    for (double s : sigma) EXPECT_GE(s, 1e-9);
  }
  std::vector<double> wrong(3, 1.0);
  EXPECT_THROW(mutate(x, wrong, rule, rng), std::invalid_argument);
}

TEST(EvolutionStrategy, RecombinationTakesFromBothParents) {
  Rng rng(2);
  const Individual a{{0, 0, 0, 0, 0, 0, 0, 0}, {1, 1}}, b{{1, 1, 1, 1, 1, 1, 1, 1}, {3, 5}};
  const Individual d = recombine(a, b, Recombination::Discrete, Recombination::Intermediate, rng);
  int from_b = 0;
  for (double v : d.x) {
    EXPECT_TRUE(v == 0 || v == 1);
    from_b += v == 1;
  }
  EXPECT_GT(from_b, 0);
  EXPECT_LT(from_b, 8);
  EXPECT_EQ(d.sigma, (std::vector<double>{2, 3}));
  const Individual m = recombine(a, b, Recombination::Intermediate, Recombination::None, rng);
  EXPECT_EQ(m.x, std::vector<double>(8, 0.5));
  EXPECT_EQ(m.sigma, a.sigma);
}

TEST(EvolutionStrategy, OffspringStayInTheBox) {
  StrategyParams params;
  params.lower = {-1, 0};
  params.upper = {1, 0.5};
  Rng rng(3);
  const std::vector<Individual> parents = {{{0.9, 0.4}, {10, 10}}};
  for (const Individual& o : make_offspring(parents, params, StepRule::standard(2, 2), rng)) {
    EXPECT_GE(o.x[0], -1.0);
    EXPECT_LE(o.x[0], 1.0);
    EXPECT_GE(o.x[1], 0.0);
    EXPECT_LE(o.x[1], 0.5);
  }
}

TEST(EvolutionStrategy, RejectsParametersThatDoNotFit) {
  StrategyParams comma;
  comma.mu = 10;
  comma.lambda = 5;
  EXPECT_THROW(EvolutionStrategy(comma, {start_point(3, 3)}, 1), std::invalid_argument);
  EXPECT_THROW(EvolutionStrategy(StrategyParams{}, {}, 1), std::invalid_argument);
  EXPECT_THROW(EvolutionStrategy(StrategyParams{}, {start_point(3, 2)}, 1), std::invalid_argument);
  EXPECT_THROW(EvolutionStrategy(StrategyParams{}, {start_point(3, 3), start_point(4, 4)}, 1),
               std::invalid_argument);
  StrategyParams box;
  box.lower = {0, 0};
  box.upper = {1, 1};
  EXPECT_THROW(EvolutionStrategy(box, {start_point(3, 3)}, 1), std::invalid_argument);
}
