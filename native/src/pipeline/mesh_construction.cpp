#include "mesh_construction.h"

#include <algorithm>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_surfaces.h"
#include "csgfit/model/voxelize.h"

namespace csgfit {

namespace {

// The construction explains the mesh when it misses or adds at most this share of the solid's
// samples: what is left is the file's rounding on the faces, not a feature a search would find.
constexpr double kExplainedShare = 0.002;
// and when its voxels agree with the mesh's this well: the samples are the construction's own,
// and faces read wrongly (a ball taken for strips of cylinders) can satisfy them with a tree
// that the voxels show to be wrong.
constexpr double kExplainedGridIoU = 0.98;
// The grid that measures the tree reaches at most this share of the mesh's longest side past
// the mesh's box (margin_for in fit_mesh.cpp caps the search's grid the same way).
constexpr double kMostReach = 0.25;

// Options for the part's voxels of size `voxel_size` on a box that holds the mesh and the
// tree: a ball cut by three bores reaches past the mesh's own box (the bores took its poles),
// and the evaluator counts what of the tree's box lies beyond the grid as excess. The box goes
// at most kMostReach of the mesh's longest side past the mesh's own, as the search's does.
VoxelizeOptions covering(const TriangleMesh& mesh, const Node3D& tree, double voxel_size, int margin) {
  VoxelizeOptions o;
  o.voxel_size = voxel_size;
  o.margin = margin;
  const Bounds3 t = tree_bounds(tree);
  if (!(t.lo[0] <= t.hi[0] && t.lo[1] <= t.hi[1] && t.lo[2] <= t.hi[2]) || mesh.vertices.empty()) return o;
  Bounds3 m{mesh.vertices.front(), mesh.vertices.front()};
  for (const Vec3& v : mesh.vertices) m = merged(m, Bounds3{v, v});
  const double reach = kMostReach * std::max({m.hi[0] - m.lo[0], m.hi[1] - m.lo[1], m.hi[2] - m.lo[2]});
  o.cover_box = true;
  for (int a = 0; a < 3; ++a) {
    o.box_lo[a] = std::max(t.lo[a], m.lo[a] - reach);
    o.box_hi[a] = std::min(t.hi[a], m.hi[a] + reach);
  }
  return o;
}

}  // namespace

ConstructedFit construct_mesh_fit(const TriangleMesh& local, double voxel_size, int margin,
                                  const FitOptions3D& options, std::chrono::steady_clock::time_point deadline) {
  ConstructedFit out;
  ConstructionOptions co;
  co.kinds = analytic_kinds(options.primitives);
  co.seed = options.seed;
  co.deadline = deadline;
  out.construction = construct_from_surfaces(segment_mesh_surfaces(local), co);
  if (!out.construction.built) return out;
  Node3D tree = out.construction.tree;
  VoxelizeOptions vo = covering(local, tree, voxel_size, margin);
  out.grid = voxelize(local, vo);
  vo.lattice_shift = kStaggeredShift;
  const VoxelGrid staggered = voxelize(local, vo);
  TreeEvaluator3D ev(out.grid, staggered, tree);
  const double k = options.k >= 0 ? options.k : default_k3d(out.grid);
  FitStats& s = out.fit.stats;
  set_mismatch_stats(s, ev.mismatch(), out.grid.count() + staggered.count(), tree.primitive_count(), 2 * k);
  s.evaluations = ev.evaluations();
  s.stop_reason = "constructed";
  out.fit.tree = std::move(tree);
  out.built = true;
  out.explains = out.construction.missed + out.construction.extra <= kExplainedShare && s.iou >= kExplainedGridIoU;
  return out;
}

}  // namespace csgfit
