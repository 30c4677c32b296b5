// Bitmap -> tree: seed 003's and the greedy cover's first trees, seed 000's search over
// islands, the final polish and the design values.
#include "csgfit/pipeline/fit_bitmap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/features/boundary_curves.h"
#include "csgfit/features/features2d.h"
#include "optimize_last.h"
#include "csgfit/optimise/prune.h"
#include "csgfit/optimise/snap2d.h"
#include "csgfit/refine/contour_fit2d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/seed/decompose2d.h"
#include "csgfit/seed/boundary_primitives.h"
#include "csgfit/seed/candidate_selection.h"
#include "csgfit/seed/greedy2d.h"
#include "pipeline/fit_request.h"
#include "pipeline/problems.h"
#include "search/islands.h"
#include "search/operators2d.h"

namespace csgfit {

double default_k(int width, int height, double k_at_128) {
  return k_at_128 * static_cast<double>(width) * static_cast<double>(height) / (128.0 * 128.0);
}

using Clock = std::chrono::steady_clock;

Problem2D make_problem2d(const Bitmap& target, const FitOptions& options, Clock::time_point start) {
  Problem2D pb;
  pb.target = &target;
  pb.k = options.k >= 0 ? options.k
                        : default_k(target.width(), target.height(), options.search.k_at_128);
  pb.params = options.search;
  for (PrimitiveKind k : {PrimitiveKind::Rectangle, PrimitiveKind::Circle, PrimitiveKind::Ellipse,
                          PrimitiveKind::Triangle})
    if (options.primitives.has(k)) pb.kinds.push_back(k);
  pb.new_leaf_opt = LocalOptOptions::pattern(pb.params.local_iterations, 2.0, 0.25);
  pb.all_leaf_opt = LocalOptOptions::pattern(3, 0.5, 0.25);
  // --time bounds the wall time: no single tree's optimisation may run past it.
  pb.new_leaf_opt.deadline = pb.all_leaf_opt.deadline =
      at_fraction(start, options.time_limit, 1.0);
  pb.shape_peaks = distance_peaks(target, 1.0, 64);
  pb.background_peaks = distance_peaks(target.inverted(), 1.0, 64);
  const BoundaryPrimitives drawn = boundary_primitives(target, options.primitives);
  for (const Primitive& p : drawn.positives) pb.proposals.push_back({p, true});
  for (const Primitive& p : drawn.holes) pb.proposals.push_back({p, false});
  return pb;
}

SeedTrees2D seed_trees2d(const Bitmap& target, const FitOptions& options, const Problem2D& pb,
                         Operators2D& ops, Clock::time_point start, std::size_t& evaluations) {
  SeedTrees2D s;
  if (!pb.params.seed_with_decomposition) return s;
  if (options.primitives.has(PrimitiveKind::Rectangle)) {
    DecomposeOptions dopt;
    dopt.primitives = options.primitives;
    dopt.k = pb.k;
    Node seed_tree = decompose(target, dopt);
    LocalOptOptions polish = LocalOptOptions::pattern(pb.params.local_iterations, 1.0, 0.125);
    polish.deadline = at_fraction(start, options.time_limit, 0.5);
    {
      TreeEvaluator ev(target, seed_tree);
      optimize_leaves(ev, polish);
      evaluations += ev.evaluations();
    }
    s.decomposition = ops.evaluate(std::move(seed_tree), {});
  }
  GreedyOptions gopt;
  gopt.primitives = options.primitives;
  gopt.k = pb.k;
  for (const auto& p : pb.proposals) (p.positive ? gopt.proposals : gopt.cut_proposals).push_back(p.primitive);
  s.greedy = ops.evaluate(greedy_cover(target, gopt), {});
  if (auto chosen = select_candidates(target, gopt.proposals, gopt.cut_proposals, pb.k))
    s.selection = ops.evaluate(std::move(*chosen), {});
  return s;
}

namespace {

using Candidate = Candidate2D;
using Island = islands::Island<Operators2D>;
using Seeds = SeedTrees2D;

// Initial populations, built in parallel: the seed trees (in turn) where there are any,
// seed 000's random trees otherwise.
void fill_populations(std::vector<Island>& isles, const Seeds& seeds, const Problem2D& pb,
                      std::size_t per_island, const std::function<bool()>& out_of_time) {
  islands::in_parallel<Operators2D>(isles, [&](Island& isle) {
    const std::vector<const Candidate*> seeded = seeds.present();
    for (std::size_t j = 0; j < per_island; ++j) {
      if (!seeded.empty()) {
        isle.population.push_back(*seeded[j % seeded.size()]);
        continue;
      }
      if (out_of_time() && !isle.population.empty()) {
        isle.population.push_back(isle.population.front());
        continue;
      }
      std::vector<Primitive> fresh;
      const int count =
          rnd::norm_count(isle.ops.rng(), pb.params.initial_size_mean, pb.params.initial_size_sd);
      Node t = isle.ops.random_subtree(count, fresh);
      isle.population.push_back(isle.ops.evaluate(std::move(t), fresh));
      ++isle.ops.trees;
    }
  });
}

// The best tree per structure, for the alternatives.
class Archive {
 public:
  void remember(const Candidate& c) {
    if (!std::isfinite(c.score)) return;
    const std::string key = structure_string(c.tree);
    auto it = by_structure_.find(key);
    if (it == by_structure_.end() || c.score < it->second.score) by_structure_[key] = c;
  }
  // Up to `count` trees of other structures than `best`'s, best first.
  std::vector<const Candidate*> runners_up(const Candidate& best, std::size_t count) const {
    const std::string best_key = structure_string(best.tree);
    std::vector<const Candidate*> ranked;
    for (const auto& [key, c] : by_structure_)
      if (key != best_key) ranked.push_back(&c);
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const Candidate* a, const Candidate* b) { return a->score < b->score; });
    if (ranked.size() > count) ranked.resize(count);
    return ranked;
  }

 private:
  std::map<std::string, Candidate> by_structure_;
};

// The winner at sub-pixel steps, pruned and given design values where that costs (almost)
// nothing, then its boundaries moved off pixel centres.
Candidate polish(Candidate best, const Bitmap& target, const FitOptions& options,
                 const Problem2D& pb, Clock::time_point start, std::size_t& evaluations) {
  LocalOptOptions lo = LocalOptOptions::pattern(pb.params.local_iterations, 0.5, 1.0 / 32);
  lo.deadline = at_fraction(start, options.time_limit, 1.05);  // a grace: it makes the numbers clean
  Node tree = best.tree;
  {
    TreeEvaluator ev(target, tree);
    optimize_leaves(ev, lo);
    // The pattern search stops where no single step lowers the mismatch. A least-squares fit
    // to the bitmap's sub-pixel contour puts each edge where the drawn edge was, and from
    // there the pattern search often finds fewer mismatched pixels.
    BoundaryFitOptions on_contour;
    on_contour.deadline = lo.deadline;
    if (refine_to_contour(ev, contour_of(target).points, on_contour) > 0) optimize_leaves(ev, lo);
    evaluations += ev.evaluations();
  }
  prune(tree, target, pb.k);
  LocalOptOptions refit = LocalOptOptions::pattern(4, 1.0, 1.0 / 16);
  refit.deadline = lo.deadline;
  prune_refitted(tree, target, pb.k, refit, evaluations);
  TreeEvaluator ev(target, tree);
  // Designer-friendly numbers for at most 0.2 % of the shape's pixels (and never more than
  // one primitive's worth of score).
  const double snap_budget = std::min(pb.k, 0.002 * static_cast<double>(target.count()));
  const DesignSnaps snaps = snap_to_design_values(ev, options.primitives, snap_budget);
  evaluations += ev.evaluations();
  Candidate polished{tree, ev.mismatch(), tree.primitive_count(), 0};
  polished.score = score(polished.mismatch, polished.primitives, pb.k);
  // Snapping may cost a little score; it is kept when the tree is otherwise no worse.
  if (polished.score <= best.score + snap_budget + snaps.straightening_cost) best = polished;
  TreeEvaluator tied(target, best.tree);
  untie(tied);
  return best;
}

FitStats stats_of(const Candidate& c, const Bitmap& target, double k) {
  FitStats s;
  set_mismatch_stats(s, c.mismatch, target.count(), c.primitives, k);
  return s;
}

}  // namespace

FitResult fit_bitmap(const Bitmap& target, const FitOptions& options,
                     const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  check_search_options(options.time_limit, options.threads, options.k);
  check_fit_request(target, options.primitives, options.time_limit);
  const Problem2D pb = make_problem2d(target, options, start);
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  const int count =
      std::min(islands::island_count(options.threads), std::max(1, pb.params.population));
  const std::size_t per_island = static_cast<std::size_t>(std::max(2, pb.params.population / count));
  std::vector<Island> isles = islands::make_islands<Operators2D>(pb, options.seed, count);
  std::size_t evaluations = 0;
  const Seeds seeds = seed_trees2d(target, options, pb, isles[0].ops, start, evaluations);
  fill_populations(isles, seeds, pb, per_island, [&] {
    return (cancel && cancel->load(std::memory_order_relaxed)) || elapsed() >= options.time_limit;
  });

  Archive archive;
  Candidate unknown;
  unknown.score = std::numeric_limits<double>::infinity();
  const islands::Limits limits{start, options.time_limit, options.time_limit, cancel, progress};
  islands::Outcome<Candidate> found = islands::search<Operators2D>(
      isles, unknown, pb.params, limits, evaluations, [&](const Island& isle) {
        for (const Candidate& c : isle.population) archive.remember(c);
      });
  evaluations += found.evaluations;
  const Candidate best = polish(found.best, target, options, pb, start, evaluations);

  FitResult result;
  result.width = target.width();
  result.height = target.height();
  result.tree = best.tree;
  result.stats = stats_of(best, target, pb.k);
  if (options.optimize_tree)
    optimize_last(result.tree, result.stats, options.seed, [&](const Node& a, const Node& b) {
      return render(a, target.width(), target.height()) == render(b, target.width(), target.height());
    });
  result.stats.evaluations = evaluations;
  result.stats.trees = found.trees;
  result.stats.seconds = elapsed();
  result.stats.stop_reason = found.stop_reason;
  if (options.alternatives > 0)
    for (const Candidate* c : archive.runners_up(best, static_cast<std::size_t>(options.alternatives)))
      result.alternatives.push_back(FitTree{c->tree, stats_of(*c, target, pb.k)});
  return result;
}

}  // namespace csgfit
