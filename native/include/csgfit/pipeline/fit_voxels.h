// Voxel grid -> 3D CSG tree: seed 003's 3D decomposition, the 3D local optimiser and a seed-000
// hill climb behind one call (the 3D twin of fit.h; the seed-004 evolution strategy comes later).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/search/params.h"
#include "csgfit/search/stats.h"

namespace csgfit {

/// Trees and primitives read off the input's surface (fit_mesh fills them from the mesh): the
/// search starts from the best of these trees and seed 003's decomposition, and ADD and INT try
/// these primitives beside their match to the residual.
struct SurfaceSeeds {
  std::vector<Node3D> trees;
  std::vector<Primitive3D> positives;  ///< convex surfaces: solids to add (round ones also trim)
  std::vector<Primitive3D> negatives;  ///< concave surfaces: solids to cut away
  bool empty() const { return trees.empty() && positives.empty() && negatives.empty(); }
};

/// Everything a 3D fit takes besides the voxels.
struct FitOptions3D {
  double k = -1;               ///< size weight in voxels; < 0 means default_k3d(target)
  PrimitiveSet3D primitives = PrimitiveSet3D::matchable();
  double time_limit = 10;      ///< seconds of wall time for the whole fit
  int threads = 0;             ///< 0 = all cores
  std::uint64_t seed = 1;
  SearchParams search = SearchParams::for_3d();  ///< islands, odds, convergence (max_stale)
  bool optimize_tree = true;   ///< seed 001's optimiser as the last stage (same solid, smaller tree)
  SurfaceSeeds surface;        ///< empty: the search knows only the voxels
};

/// k for a grid: 140 voxels per primitive per million voxels of the grid (the target's whole
/// box, margins included), at least 8. A primitive must then explain a piece of about 1/19 of
/// the grid's mean side cubed, which keeps the smallest kept feature at the same fraction of
/// the part's size at every resolution. (100 per million, the 2D default's rule in 3D, gave
/// 67 primitives on the InverseCSG CAD meshes where InverseCSG's programs have 61; 200 gave
/// 37.7 at IoU 0.9729 once the surface seeds came, 140 gives 42.1 at 0.9739.)
double default_k3d(const VoxelGrid& target);

struct FitResult3D {
  Node3D tree;      ///< the best tree, in the target's model coordinates
  FitStats stats;   ///< excess/uncovered in voxels, iou over the target's grid
};

/// Fits a 3D CSG tree to `target`. Throws std::invalid_argument when the target has no set
/// voxel ("no shape found") or the options are invalid. Honours `cancel` and the progress
/// callback's return value (stop_reason "cancelled", best tree so far). Same seed and threads
/// give the same tree when the search ends by convergence (a time limit cuts it where the
/// clock says).
FitResult3D fit_voxels(const VoxelGrid& target, const FitOptions3D& options,
                       const ProgressCallback& progress = nullptr,
                       const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
