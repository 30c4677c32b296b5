// Seed 000's hill climbing on voxels, seeded with seed 003's 3D decomposition.
#include "csgfit/pipeline/fit_voxels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <thread>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/features3d.h"
#include "csgfit/optimise/prune.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/seed/decompose3d.h"
#include "model/random.h"

namespace csgfit {

double default_k3d(const VoxelGrid& target) {
  const double n = static_cast<double>(target.nx()) * target.ny() * target.nz();
  return std::max(8.0, 200.0 * n / 1e6);
}

namespace {

using Clock = std::chrono::steady_clock;
using rnd::pick;
using rnd::Rng;
using rnd::splitmix;
using rnd::uniform;

struct Candidate {
  Node3D tree;
  Mismatch mismatch;
  std::size_t primitives = 0;
  double score = std::numeric_limits<double>::infinity();
  VoxelGrid result;  // the tree's voxels, for the residual
};

// Half-extents of a primitive in its local frame: what MOD and REP keep when changing its kind.
Vec3 half_extents(const Primitive3D& p) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::TriangularPrism: return {d[0] / 2, d[1] / 2, d[2] / 2};
    case PrimitiveKind3D::Cylinder: return {d[0], d[0], d[2] / 2};
    case PrimitiveKind3D::Cone: {
      const double r = std::max(d[0], d[1]);
      return {r, r, d[2] / 2};
    }
    case PrimitiveKind3D::Torus: return {d[0] + d[1], d[0] + d[1], d[1]};
    case PrimitiveKind3D::Sphere:
    case PrimitiveKind3D::Ellipsoid: return d;
  }
  return d;
}

Primitive3D with_kind(const Primitive3D& p, PrimitiveKind3D kind, const Vec3& he) {
  const double cx = p.cx, cy = p.cy, cz = p.cz;
  const Quaternion& q = p.rotation;
  Primitive3D out;
  switch (kind) {
    case PrimitiveKind3D::Box: out = Primitive3D::box(cx, cy, cz, 2 * he[0], 2 * he[1], 2 * he[2], q); break;
    case PrimitiveKind3D::Sphere: out = Primitive3D::sphere(cx, cy, cz, (he[0] + he[1] + he[2]) / 3); break;
    case PrimitiveKind3D::Cylinder:
      out = Primitive3D::cylinder(cx, cy, cz, (he[0] + he[1]) / 2, 2 * he[2], q);
      break;
    case PrimitiveKind3D::Cone:
      out = Primitive3D::cone(cx, cy, cz, (he[0] + he[1]) / 2, (he[0] + he[1]) / 4, 2 * he[2], q);
      break;
    case PrimitiveKind3D::Ellipsoid: out = Primitive3D::ellipsoid(cx, cy, cz, he[0], he[1], he[2], q); break;
    case PrimitiveKind3D::Torus: {
      const double r = std::max(he[2], 0.25 * (he[0] + he[1]) / 2);
      out = Primitive3D::torus(cx, cy, cz, std::max(r, (he[0] + he[1]) / 2 - r), r, q);
      break;
    }
    case PrimitiveKind3D::TriangularPrism:
      out = Primitive3D::prism(cx, cy, cz, 2 * he[0], 2 * he[1], 2 * he[2], 0, q);
      break;
  }
  out.normalize();
  return out;
}

// Everything the islands share (read-only while they run).
struct Problem {
  const VoxelGrid* target = nullptr;
  double k = 100;
  std::vector<PrimitiveKind3D> kinds;
  PrimitiveSet3D primitives;
  LocalOptOptions new_leaf_opt, all_leaf_opt;
  // Round primitives matched to the whole target: what INT intersects a tree with to trim its
  // outline (a cube intersected with a sphere, a plate with a cylinder).
  std::vector<Primitive3D> hulls;
};

class Island {
 public:
  Island(const Problem& pb, std::uint64_t seed) : pb_(pb), rng_(seed) {}

  Candidate current;
  std::size_t trees = 0, evaluations = 0, stale = 0;

  // Optimises the fresh leaves (all leaves when polish_all) and scores the tree. Pruning is
  // left to finish(): most perturbations are rejected, and for those it would be wasted.
  Candidate evaluate(Node3D tree, const std::vector<Primitive3D>& fresh, bool polish_all) {
    Candidate c;
    if (!simplify(tree)) return c;
    TreeEvaluator3D ev(*pb_.target, tree);
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < ev.leaf_count() && !fresh.empty(); ++i)
      if (std::find(fresh.begin(), fresh.end(), ev.leaf(i)) != fresh.end()) idx.push_back(i);
    if (!idx.empty()) optimize_leaves(ev, pb_.new_leaf_opt, idx);
    if (polish_all) optimize_leaves(ev, pb_.all_leaf_opt);
    evaluations += ev.evaluations();
    c.mismatch = ev.mismatch();
    c.primitives = tree.primitive_count();
    c.score = score(c.mismatch, c.primitives, pb_.k);
    c.result = ev.result();
    c.tree = std::move(tree);
    return c;
  }

  // Prunes an accepted tree and rescores it.
  void finish(Candidate& c) {
    if (prune(c.tree, *pb_.target, pb_.k) == 0) return;
    TreeEvaluator3D ev(*pb_.target, c.tree);
    evaluations += ev.evaluations() + c.tree.primitive_count();
    c.mismatch = ev.mismatch();
    c.primitives = c.tree.primitive_count();
    c.score = score(c.mismatch, c.primitives, pb_.k);
    c.result = ev.result();
  }

  // ADD at the residual: the thick part (one erosion removes the one-voxel skins a slightly
  // misplaced primitive leaves) of what the tree gets wrong, matched by seed 003's matcher.
  bool add_at_residual(Node3D& tree, const VoxelGrid& raster, std::vector<Primitive3D>& fresh) {
    const bool as_union = rng_() & 1;
    VoxelGrid residual = as_union ? *pb_.target : raster;
    residual.subtract(as_union ? raster : *pb_.target);
    std::vector<Region3D> comps = connected_regions3d(erode6(residual), 6);
    if (comps.empty()) return false;
    std::stable_sort(comps.begin(), comps.end(),
                     [](const Region3D& a, const Region3D& b) { return a.volume > b.volume; });
    const std::size_t n = std::min<std::size_t>(comps.size(), 6);
    const Region3D& core = comps[std::min(pick(rng_, n), pick(rng_, n))];
    // Grow the core back into the residual around it.
    const int lo[3] = {core.lo[0] - 1, core.lo[1] - 1, core.lo[2] - 1};
    const int hi[3] = {core.hi[0] + 1, core.hi[1] + 1, core.hi[2] + 1};
    std::vector<Region3D> around = connected_regions3d(crop(residual, lo, hi, 0), 6);
    if (around.empty()) return false;
    const Region3D* region = &around.front();
    for (const Region3D& r : around)
      if (r.volume > region->volume) region = &r;
    auto match = match_region3d(region->mask, pb_.primitives);
    if (!match) return false;
    fresh.push_back(match->primitive);
    const std::size_t nodes = tree.node_count();
    Node3D* at = (rng_() % 2 == 0) ? &tree : node_at(tree, pick(rng_, nodes));
    Node3D old = std::move(*at);
    *at = Node3D::op(as_union ? NodeKind::Union : NodeKind::Difference,
                     {std::move(old), Node3D::leaf(match->primitive)});
    return true;
  }

  bool cut(Node3D& tree) {
    const std::size_t n = tree.node_count();
    if (n <= 1) return false;
    const std::size_t idx = 1 + pick(rng_, n - 1);
    std::size_t counter = 0;
    std::function<bool(Node3D&)> go = [&](Node3D& node) -> bool {
      ++counter;
      for (std::size_t c = 0; c < node.children.size(); ++c) {
        if (counter == idx) {
          node.children.erase(node.children.begin() + static_cast<std::ptrdiff_t>(c));
          return true;
        }
        if (go(node.children[c])) return true;
      }
      return false;
    };
    return go(tree);
  }

  // MOD (same place and size, another kind) or REP (another kind, a new orientation).
  bool change_kind(Node3D& tree, std::vector<Primitive3D>& fresh, bool new_orientation) {
    if (pb_.kinds.size() < 2 && !new_orientation) return false;
    std::vector<Primitive3D*> ls = leaves(tree);
    Primitive3D* p = ls[pick(rng_, ls.size())];
    PrimitiveKind3D kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
    if (!new_orientation)
      while (kind == p->kind) kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
    Vec3 he = half_extents(*p);
    Primitive3D np = *p;
    if (new_orientation) {
      for (double& h : he) h *= uniform(rng_, 0.6, 1.4);
      np.rotation = Quaternion::from_euler_deg(uniform(rng_, -180, 180), uniform(rng_, -90, 90),
                                               uniform(rng_, -180, 180));
    }
    *p = with_kind(np, kind, he);
    fresh.push_back(*p);
    return true;
  }

  // INT: the tree (or a subtree) intersected with a round primitive matched to the whole
  // target, a little larger than the match so that it trims rather than eats.
  bool intersect(Node3D& tree, std::vector<Primitive3D>& fresh) {
    if (pb_.hulls.empty()) return false;
    Primitive3D hull = pb_.hulls[pick(rng_, pb_.hulls.size())];
    const double grow = uniform(rng_, 1.0, 1.3);
    for (double& d : hull.dims) d *= grow;
    hull.normalize();
    fresh.push_back(hull);
    const std::size_t nodes = tree.node_count();
    Node3D* at = (rng_() % 4 != 0) ? &tree : node_at(tree, pick(rng_, nodes));
    Node3D old = std::move(*at);
    *at = Node3D::op(NodeKind::Intersection, {std::move(old), Node3D::leaf(hull)});
    return true;
  }

  Candidate perturb(const Candidate& parent) {
    Node3D tree = parent.tree;
    std::vector<Primitive3D> fresh;
    const double r = uniform(rng_, 0, 1);
    bool done = false;
    if (r < 0.47) done = add_at_residual(tree, parent.result, fresh);
    else if (r < 0.5) done = intersect(tree, fresh);
    else if (r < 0.7) done = cut(tree);
    else if (r < 0.85) done = change_kind(tree, fresh, false);
    if (!done) done = change_kind(tree, fresh, true);
    ++trees;
    // A cut changes no primitive: its neighbours get a short polish instead.
    return evaluate(std::move(tree), fresh, fresh.empty());
  }

  void run(std::size_t count, const std::function<bool()>& should_stop) {
    for (std::size_t t = 0; t < count; ++t) {
      if (should_stop()) return;
      Candidate child = perturb(current);
      if (child.score < current.score - 1e-9) {
        finish(child);
        current = std::move(child);
        stale = 0;
      } else {
        ++stale;
      }
    }
  }

 private:
  const Problem& pb_;
  Rng rng_;
};

}  // namespace

FitResult3D fit_voxels(const VoxelGrid& target, const FitOptions3D& options,
                       const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  if (target.empty() || target.count() == 0) throw std::invalid_argument("no shape found");
  if (options.primitives.empty()) throw std::invalid_argument("no primitive type allowed");
  if (!options.primitives.has(PrimitiveKind3D::Box))
    throw std::invalid_argument("the 3D fit needs boxes among the primitives");
  if (!(options.time_limit > 0)) throw std::invalid_argument("the time budget must be positive");

  Problem pb;
  pb.target = &target;
  pb.k = options.k >= 0 ? options.k : default_k3d(target);
  pb.primitives = options.primitives;
  for (int i = 0; i <= static_cast<int>(PrimitiveKind3D::TriangularPrism); ++i)
    if (options.primitives.has(static_cast<PrimitiveKind3D>(i)))
      pb.kinds.push_back(static_cast<PrimitiveKind3D>(i));
  pb.new_leaf_opt.max_sweeps = 30;
  pb.new_leaf_opt.initial_step = 1.0;
  pb.new_leaf_opt.min_step = 0.25;
  pb.all_leaf_opt.max_sweeps = 2;
  pb.all_leaf_opt.initial_step = 0.5;
  pb.all_leaf_opt.min_step = 0.25;
  for (PrimitiveKind3D kind : {PrimitiveKind3D::Sphere, PrimitiveKind3D::Cylinder, PrimitiveKind3D::Ellipsoid}) {
    if (!options.primitives.has(kind)) continue;
    PrimitiveSet3D only;
    only.add(kind);
    if (auto m = match_region3d(target, only)) pb.hulls.push_back(m->primitive);
  }
  // --time bounds the wall time: no single tree's optimisation may run past it.
  const auto budget_end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.time_limit));
  pb.new_leaf_opt.deadline = pb.all_leaf_opt.deadline = budget_end;
  pb.new_leaf_opt.cancel = pb.all_leaf_opt.cancel = cancel;

  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  std::atomic<bool> stop_now{false};
  // The search stops early enough for the final polish, which costs about what the seed's did.
  double search_limit = options.time_limit;
  auto should_stop = [&] {
    if (stop_now.load(std::memory_order_relaxed)) return true;
    if ((cancel && cancel->load(std::memory_order_relaxed)) || elapsed() >= search_limit) {
      stop_now = true;
      return true;
    }
    return false;
  };

  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int islands = std::max(1, options.threads > 0 ? options.threads : static_cast<int>(hw));
  std::vector<Island> isles;
  isles.reserve(static_cast<std::size_t>(islands));
  for (int i = 0; i < islands; ++i)
    isles.emplace_back(pb, splitmix(options.seed * 0x100000001b3ULL + static_cast<std::uint64_t>(i)));

  // The first tree: seed 003 in 3D, every leaf optimised, pruned.
  std::size_t evaluations = 0;
  Candidate best;
  {
    DecomposeOptions3D dopt;
    dopt.primitives = options.primitives;
    dopt.primitives.bits &= PrimitiveSet3D::matchable().bits;
    dopt.k = pb.k;
    dopt.time_limit = 0.3 * options.time_limit;
    dopt.cancel = cancel;
    Node3D seed_tree = decompose3d(target, dopt);
    LocalOptOptions polish;
    polish.max_sweeps = 20;
    polish.initial_step = 1.0;
    polish.min_step = 0.25;
    polish.deadline = start + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(0.6 * options.time_limit));
    polish.cancel = cancel;
    const double polish_start = elapsed();
    {
      TreeEvaluator3D ev(target, seed_tree);
      optimize_leaves(ev, polish);
      evaluations += ev.evaluations();
    }
    search_limit = std::max(0.5 * options.time_limit,
                            options.time_limit - 2.0 * (elapsed() - polish_start));
    best = isles[0].evaluate(std::move(seed_tree), {}, false);
    isles[0].finish(best);
  }
  for (Island& isle : isles) isle.current = best;

  auto parallel = [&](const std::function<void(Island&)>& work) {
    if (islands == 1) {
      work(isles[0]);
      return;
    }
    std::vector<std::thread> pool;
    for (int i = 1; i < islands; ++i) pool.emplace_back([&, i] { work(isles[static_cast<std::size_t>(i)]); });
    work(isles[0]);
    for (std::thread& t : pool) t.join();
  };

  std::string stop_reason = "converged";
  std::size_t stale = 0;
  const std::size_t generation = 4;
  for (std::size_t gen = 0;; ++gen) {
    std::size_t trees = 0, evals = evaluations;
    bool improved = false;
    std::size_t best_isle = 0;
    for (std::size_t i = 0; i < isles.size(); ++i) {
      trees += isles[i].trees;
      evals += isles[i].evaluations;
      if (isles[i].current.score < best.score - 1e-9) {
        best = isles[i].current;
        best_isle = i;
        improved = true;
      }
    }
    stale = improved ? 0 : stale + (gen == 0 ? 0 : generation * isles.size());
    if (progress) {
      FitProgress p;
      p.seconds = elapsed();
      p.fraction = std::min(1.0, std::max(p.seconds / options.time_limit,
                                          static_cast<double>(stale) / std::max(1, options.max_stale)));
      p.best_score = best.score;
      p.best_primitives = best.primitives;
      p.evaluations = evals;
      if (!progress(p)) stop_now = true;
    }
    const bool cancelled = (cancel && cancel->load()) || (stop_now && elapsed() < search_limit);
    if (cancelled) {
      stop_reason = "cancelled";
      break;
    }
    if (stop_now || elapsed() >= search_limit) {
      stop_reason = "time";
      break;
    }
    if (stale >= static_cast<std::size_t>(std::max(1, options.max_stale))) break;
    // The best tree moves to the island that has been stuck longest (ties: lowest index), so
    // that islands explore around good trees without all collapsing onto one at once.
    if (improved && isles.size() > 1) {
      std::size_t stuck = best_isle == 0 ? 1 : 0;
      for (std::size_t i = 0; i < isles.size(); ++i)
        if (i != best_isle && isles[i].stale > isles[stuck].stale) stuck = i;
      isles[stuck].current = best;
      isles[stuck].stale = 0;
    }
    parallel([&](Island& isle) { isle.run(generation, should_stop); });
  }
  std::size_t all_trees = 0;
  for (Island& isle : isles) {
    if (isle.current.score < best.score - 1e-9) best = isle.current;
    evaluations += isle.evaluations;
    all_trees += isle.trees;
  }

  // Final polish of the winner at sub-voxel steps.
  {
    LocalOptOptions polish;
    polish.max_sweeps = 20;
    polish.initial_step = 0.5;
    polish.min_step = 1.0 / 16;
    // The polish ends with the budget (the search stopped early enough to leave it time).
    polish.deadline = start + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(options.time_limit));
    polish.cancel = cancel;
    Node3D tree = best.tree;
    {
      TreeEvaluator3D ev(target, tree);
      optimize_leaves(ev, polish);
      evaluations += ev.evaluations();
    }
    prune(tree, target, pb.k);
    TreeEvaluator3D ev(target, tree);
    evaluations += ev.evaluations();
    Candidate polished{tree, ev.mismatch(), tree.primitive_count(), 0, VoxelGrid()};
    polished.score = score(polished.mismatch, polished.primitives, pb.k);
    if (polished.score <= best.score) best = std::move(polished);
  }

  FitResult3D result;
  result.tree = best.tree;
  FitStats& s = result.stats;
  set_mismatch_stats(s, best.mismatch, target.count(), best.primitives, pb.k);
  s.evaluations = evaluations;
  s.trees = all_trees;
  s.seconds = elapsed();
  s.stop_reason = stop_reason;
  return result;
}

}  // namespace csgfit
