#include "csgfit/search/gp_search.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "search/gp_operators.h"
#include "search/untie_points.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;

struct Island {
  rnd::Rng rng;
  std::vector<std::size_t> subset;
  std::vector<GpIndividual> parents;
  std::size_t evaluations = 0;
};

std::vector<std::size_t> draw_subset(std::size_t points, std::size_t size, rnd::Rng& rng) {
  std::vector<std::size_t> all(points);
  for (std::size_t i = 0; i < points; ++i) all[i] = i;
  if (size >= points) return all;
  for (std::size_t i = 0; i < size; ++i) std::swap(all[i], all[i + rnd::pick(rng, points - i)]);
  all.resize(size);
  std::sort(all.begin(), all.end());
  return all;
}

void evaluate(GpIndividual& g, const gp::Context& c, const FitnessWeights& w, Island& island) {
  g.fitness = point_fitness(g.tree, *c.target, w, *c.subset).fitness;
  ++island.evaluations;
}

// One offspring: a parent, maybe crossed with another, one structural change at times, then
// the terminal mutation the seed applies to every individual.
GpIndividual offspring(const Island& island, const gp::Context& c, rnd::Rng& rng) {
  const std::vector<GpIndividual>& p = island.parents;
  GpIndividual child = p[rnd::pick(rng, p.size())];
  if (p.size() > 1 && rnd::uniform(rng, 0, 1) < 0.15)
    child = gp::exchange_subtrees(child, p[rnd::pick(rng, p.size())], rng);
  const double r = rnd::uniform(rng, 0, 1);
  if (r < 0.12) gp::insert_terminal(child, c, rng);
  else if (r < 0.20) gp::delete_subtree(child, rng);
  else if (r < 0.25) gp::mutate_relation(child, rng);
  else if (r < 0.30) gp::replace_terminal(child, c, rng);
  if (!gp::tidy(child, c)) child = p.front();
  gp::mutate_terminals(child, c, rng);
  gp::tidy(child, c);
  return child;
}

void select_best(std::vector<GpIndividual>& parents, std::vector<GpIndividual> children,
                 es::Selection selection, std::size_t mu) {
  if (selection == es::Selection::Plus)
    children.insert(children.begin(), parents.begin(), parents.end());
  std::stable_sort(children.begin(), children.end(),
                   [](const GpIndividual& a, const GpIndividual& b) { return a.fitness > b.fitness; });
  children.resize(std::min(mu, children.size()));
  parents = std::move(children);
}

// A generation ends early at the deadline: large trees make one slow, and the budget is the
// user's (a search stopped by the clock is not reproducible anyway).
void generation(Island& island, const gp::Context& c, const GpParams& params, Clock::time_point deadline) {
  std::vector<GpIndividual> children;
  for (std::size_t k = 0; k < params.lambda && Clock::now() < deadline; ++k) {
    children.push_back(offspring(island, c, island.rng));
    evaluate(children.back(), c, params.weights, island);
  }
  if (!children.empty()) select_best(island.parents, std::move(children), params.selection, params.mu);
}

// Sparse migration (Sec. 3): each island's worst is replaced by a recombination of its best
// and its neighbour's, so partial solutions travel around the ring.
void migrate(std::vector<Island>& islands, std::vector<gp::Context>& contexts, const GpParams& params) {
  const std::size_t n = islands.size();
  if (n < 2) return;
  std::vector<GpIndividual> bests;
  for (const Island& i : islands) bests.push_back(i.parents.front());
  for (std::size_t i = 0; i < n; ++i) {
    Island& island = islands[i];
    GpIndividual child = gp::exchange_subtrees(bests[i], bests[(i + n - 1) % n], island.rng);
    if (!gp::tidy(child, contexts[i])) continue;
    evaluate(child, contexts[i], params.weights, island);
    if (child.fitness > island.parents.back().fitness) island.parents.back() = std::move(child);
    select_best(island.parents, {}, es::Selection::Plus, params.mu);
  }
}

void start_island(Island& island, const gp::Context& c, const GpParams& params,
                  const std::vector<Node3D>& first, bool from_first) {
  // Every other island starts from random terminals only: a detected tree that is nearly
  // right would otherwise take over every population before the others found their parts.
  for (const Node3D& t : from_first ? first : std::vector<Node3D>{}) {
    GpIndividual g{t, {}, 0};
    if (gp::tidy(g, c)) island.parents.push_back(std::move(g));
  }
  // The rest: the patch alone (a die's face) and single terminals under random points.
  if (c.patch) island.parents.push_back(GpIndividual{Node3D::leaf(*c.patch), {}, 0});
  while (island.parents.size() < params.mu) {
    GpIndividual g{gp::seed_terminal(c, island.rng), {}, 0};
    if (gp::tidy(g, c)) island.parents.push_back(std::move(g));
  }
  for (GpIndividual& g : island.parents) gp::tidy(g, c);
  for (GpIndividual& g : island.parents) evaluate(g, c, params.weights, island);
  select_best(island.parents, {}, es::Selection::Plus, params.mu);
}

// The last step on the winner, judged on every point: each terminal whose removal does not
// lower the fitness goes (the seed's size term is weak against a patch that fits a few points
// better), until none does.
void prune(Node3D& tree, FitnessTerms& terms, const PointTarget& target, const FitnessWeights& w) {
  for (bool changed = true; changed && tree.primitive_count() > 1;) {
    changed = false;
    for (std::size_t i = 1; i < tree.node_count(); ++i) {
      Node3D trial = tree;
      if (!erase_subtree(trial, i) || !simplify(trial) || trial.primitive_count() == 0) continue;
      const FitnessTerms f = point_fitness(trial, target, w);
      if (f.fitness >= terms.fitness) {
        tree = std::move(trial), terms = f, changed = true;
        break;
      }
    }
  }
}

}  // namespace

GpResult run_gp(const PointTarget& target, const GpParams& params, const std::vector<Node3D>& first,
                const Primitive3D* patch, const ProgressCallback& progress,
                const std::atomic<bool>* cancel) {
  if (params.islands == 0 || params.mu == 0 || params.lambda == 0)
    throw std::invalid_argument("run_gp: islands, mu and lambda must be positive");
  const auto t0 = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  std::vector<Island> islands(params.islands);
  std::vector<gp::Context> contexts(params.islands);
  for (std::size_t i = 0; i < islands.size(); ++i) {
    islands[i].rng.seed(rnd::splitmix(params.seed * 1000003ULL + i));
    islands[i].subset = draw_subset(target.points.size(), params.subset, islands[i].rng);
    contexts[i] = gp::Context{&target, &islands[i].subset, params.primitives, patch, 0.02};
    start_island(islands[i], contexts[i], params, first, i % 2 == 0);
  }
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::min<std::size_t>(params.threads > 0 ? params.threads : hw, islands.size());
  const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(params.time_limit));
  GpResult out;
  out.stop = "generations";
  // The last 6 % of the time is the pruning's and the untying's (see untie_against_points).
  const double search_seconds = 0.94 * params.time_limit;
  while (out.generations < params.max_generations) {
    if (seconds() >= search_seconds) { out.stop = "time"; break; }
    if (cancel && cancel->load()) { out.stop = "cancelled"; break; }
    // Islands are independent within a generation: each has its own generator and subset.
    std::vector<std::thread> pool;
    for (std::size_t w = 1; w < workers; ++w)
      pool.emplace_back([&, w] {
        for (std::size_t i = w; i < islands.size(); i += workers) generation(islands[i], contexts[i], params, deadline);
      });
    for (std::size_t i = 0; i < islands.size(); i += workers) generation(islands[i], contexts[i], params, deadline);
    for (std::thread& t : pool) t.join();
    ++out.generations;
    if (params.migration_interval && out.generations % params.migration_interval == 0)
      migrate(islands, contexts, params);
    if (progress) {
      FitProgress p;
      p.fraction = std::min(1.0, seconds() / params.time_limit);
      p.best_score = islands.front().parents.front().fitness;
      p.best_primitives = islands.front().parents.front().tree.primitive_count();
      p.seconds = seconds();
      if (!progress(p)) { out.stop = "cancelled"; break; }
    }
  }
  // Each island's best judged on every point: subsets differ, so only the whole cloud compares.
  double best = -std::numeric_limits<double>::infinity();
  for (Island& island : islands) {
    out.evaluations += island.evaluations;
    out.island_best.push_back(island.parents.front().fitness);
    const FitnessTerms f = point_fitness(island.parents.front().tree, target, params.weights);
    if (f.fitness > best) best = f.fitness, out.tree = island.parents.front().tree, out.terms = f;
  }
  prune(out.tree, out.terms, target, params.weights);
  untie_against_points(out.tree, out.terms, target, params.weights, deadline);
  out.seconds = seconds();
  return out;
}

}  // namespace csgfit
