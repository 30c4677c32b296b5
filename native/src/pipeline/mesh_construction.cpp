#include "mesh_construction.h"

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_surfaces.h"

namespace csgfit {

namespace {

// The construction explains the mesh when it misses or adds at most this share of the solid's
// samples: what is left is the file's rounding on the faces, not a feature a search would find.
constexpr double kExplainedShare = 0.002;

}  // namespace

ConstructedFit construct_mesh_fit(const TriangleMesh& local, const VoxelGrid& grid, const VoxelGrid& staggered,
                                  const FitOptions3D& options, std::chrono::steady_clock::time_point deadline) {
  ConstructedFit out;
  ConstructionOptions co;
  co.kinds = analytic_kinds(options.primitives);
  co.seed = options.seed;
  co.deadline = deadline;
  out.construction = construct_from_surfaces(segment_mesh_surfaces(local), co);
  if (!out.construction.built) return out;
  Node3D tree = out.construction.tree;
  TreeEvaluator3D ev(grid, staggered, tree);
  const double k = options.k >= 0 ? options.k : default_k3d(grid);
  FitStats& s = out.fit.stats;
  set_mismatch_stats(s, ev.mismatch(), grid.count() + staggered.count(), tree.primitive_count(), 2 * k);
  s.evaluations = ev.evaluations();
  s.stop_reason = "constructed";
  out.fit.tree = std::move(tree);
  out.built = true;
  out.explains = out.construction.missed + out.construction.extra <= kExplainedShare;
  return out;
}

}  // namespace csgfit
