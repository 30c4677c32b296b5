// Voxels -> tree: seed 003's 3D decomposition as the first tree, the island search with the 3D
// perturbations, and a final polish at sub-voxel steps.
#include "csgfit/pipeline/fit_voxels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "csgfit/eval/evaluator3d.h"
#include "optimize_last.h"
#include "csgfit/optimise/prune.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/seed/decompose3d.h"
#include "pipeline/fit_request.h"
#include "pipeline/problems.h"
#include "search/islands.h"
#include "search/operators3d.h"

namespace csgfit {

double default_k3d(const VoxelGrid& target) {
  const double n = static_cast<double>(target.nx()) * target.ny() * target.nz();
  return std::max(8.0, 140.0 * n / 1e6);
}

using Clock = std::chrono::steady_clock;

Problem3D make_problem3d(const VoxelGrid& target, const FitOptions3D& options,
                         Clock::time_point start, const std::atomic<bool>* cancel) {
  Problem3D pb;
  pb.target = &target;
  pb.k = options.k >= 0 ? options.k : default_k3d(target);
  pb.params = options.search;
  pb.primitives = options.primitives;
  for (int i = 0; i <= static_cast<int>(PrimitiveKind3D::TriangularPrism); ++i)
    if (options.primitives.has(static_cast<PrimitiveKind3D>(i)))
      pb.kinds.push_back(static_cast<PrimitiveKind3D>(i));
  if (options.primitives.has(PrimitiveKind3D::RoundedBox)) pb.kinds.push_back(PrimitiveKind3D::RoundedBox);
  pb.new_leaf_opt = LocalOptOptions::pattern(30, 1.0, 0.25);
  pb.all_leaf_opt = LocalOptOptions::pattern(2, 0.5, 0.25);
  for (PrimitiveKind3D kind :
       {PrimitiveKind3D::Sphere, PrimitiveKind3D::Cylinder, PrimitiveKind3D::Ellipsoid}) {
    if (!options.primitives.has(kind)) continue;
    PrimitiveSet3D only;
    only.add(kind);
    if (auto m = match_region3d(target, only)) pb.hulls.push_back(m->primitive);
  }
  for (const Primitive3D& p : options.surface.positives) {
    pb.proposals.push_back({p, true});
    // A sphere or cylinder the surface shows is the hull a part was trimmed with (lock: a cube
    // intersected with a sphere).
    if (p.kind == PrimitiveKind3D::Sphere || p.kind == PrimitiveKind3D::Cylinder)
      pb.hulls.push_back(p);
  }
  for (const Primitive3D& p : options.surface.negatives) pb.proposals.push_back({p, false});
  // --time bounds the wall time: no single tree's optimisation may run past it.
  pb.new_leaf_opt.deadline = pb.all_leaf_opt.deadline =
      at_fraction(start, options.time_limit, 1.0);
  pb.new_leaf_opt.cancel = pb.all_leaf_opt.cancel = cancel;
  return pb;
}

Node3D first_tree3d(const VoxelGrid& target, const FitOptions3D& options, const Problem3D& pb,
                    Clock::time_point start, const std::atomic<bool>* cancel,
                    std::size_t& evaluations, double* polish_seconds) {
  DecomposeOptions3D dopt;
  dopt.primitives = options.primitives;
  dopt.primitives.bits &= PrimitiveSet3D::matchable().bits;
  dopt.k = pb.k;
  dopt.time_limit = 0.3 * options.time_limit;
  dopt.cancel = cancel;
  Node3D tree = decompose3d(target, dopt);
  LocalOptOptions polish = LocalOptOptions::pattern(20, 1.0, 0.25);
  polish.deadline = at_fraction(start, options.time_limit, 0.6);
  polish.cancel = cancel;
  const auto polish_start = Clock::now();
  {
    TreeEvaluator3D ev(target, tree);
    optimize_leaves(ev, polish);
    evaluations += ev.evaluations();
  }
  if (polish_seconds)
    *polish_seconds = std::chrono::duration<double>(Clock::now() - polish_start).count();
  return tree;
}

namespace {

using Candidate = Candidate3D;
using Island = islands::Island<Operators3D>;

// The first tree, scored and pruned, and when the search must stop so that the final polish,
// which costs about what the first tree's did, fits in the budget.
Candidate seed_tree(const VoxelGrid& target, const FitOptions3D& options, const Problem3D& pb,
                    Operators3D& ops, Clock::time_point start, const std::atomic<bool>* cancel,
                    std::size_t& evaluations, double& search_limit) {
  double polish_seconds = 0;
  Node3D tree = first_tree3d(target, options, pb, start, cancel, evaluations, &polish_seconds);
  search_limit = std::max(0.5 * options.time_limit, options.time_limit - 2.0 * polish_seconds);
  Candidate best = ops.evaluate(std::move(tree), {}, false);
  ops.accept(best);
  // The surface's trees, their leaves fitted to the voxels: the program where the surface
  // reads as one, else the decomposition.
  for (const Node3D& t : options.surface.trees) {
    if (t.primitive_count() == 0) continue;
    std::vector<Primitive3D> fresh;
    for (const Primitive3D* p : leaves(t)) fresh.push_back(*p);
    Candidate c = ops.evaluate(t, fresh, false);
    ops.accept(c);
    if (c.score < best.score) best = std::move(c);
  }
  return best;
}

// The winner at sub-voxel steps and pruned; kept when it is no worse.
Candidate polish(Candidate best, const VoxelGrid& target, const FitOptions3D& options,
                 const Problem3D& pb, Clock::time_point start, const std::atomic<bool>* cancel,
                 std::size_t& evaluations) {
  LocalOptOptions lo = LocalOptOptions::pattern(20, 0.5, 1.0 / 16);
  // The polish ends with the budget (the search stopped early enough to leave it time).
  lo.deadline = at_fraction(start, options.time_limit, 1.0);
  lo.cancel = cancel;
  Node3D tree = best.tree;
  {
    TreeEvaluator3D ev(target, tree);
    optimize_leaves(ev, lo);
    evaluations += ev.evaluations();
  }
  prune(tree, target, pb.k);
  TreeEvaluator3D ev(target, tree);
  evaluations += ev.evaluations();
  Candidate polished{tree, ev.mismatch(), tree.primitive_count(), 0, VoxelGrid()};
  polished.score = score(polished.mismatch, polished.primitives, pb.k);
  if (polished.score <= best.score) best = std::move(polished);
  return best;
}

}  // namespace

FitResult3D fit_voxels(const VoxelGrid& target, const FitOptions3D& options,
                       const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  check_search_options(options.time_limit, options.threads, options.k);
  check_fit_request(target, options.primitives, options.time_limit);
  if (!options.primitives.has(PrimitiveKind3D::Box))
    throw std::invalid_argument("the 3D fit needs boxes among the primitives");
  const Problem3D pb = make_problem3d(target, options, start, cancel);

  std::vector<Island> isles =
      islands::make_islands<Operators3D>(pb, options.seed, islands::island_count(options.threads));
  std::size_t evaluations = 0;
  double search_limit = options.time_limit;
  const Candidate first =
      seed_tree(target, options, pb, isles[0].ops, start, cancel, evaluations, search_limit);
  for (Island& isle : isles) isle.population.assign(1, first);

  const islands::Limits limits{start, options.time_limit, search_limit, cancel, progress};
  islands::Outcome<Candidate> found =
      islands::search<Operators3D>(isles, first, pb.params, limits, evaluations, nullptr);
  evaluations += found.evaluations;
  const Candidate best = polish(found.best, target, options, pb, start, cancel, evaluations);

  FitResult3D result;
  result.tree = best.tree;
  FitStats& s = result.stats;
  set_mismatch_stats(s, best.mismatch, target.count(), best.primitives, pb.k);
  s.evaluations = evaluations;
  s.trees = found.trees;
  s.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  s.stop_reason = found.stop_reason;
  if (options.optimize_tree)
    optimize_last(result.tree, s, options.seed,
                  [&](const Node3D& a, const Node3D& b) { return render(a, target) == render(b, target); });
  return result;
}

}  // namespace csgfit
