// Voxel grid -> 3D CSG tree: seed 003's 3D decomposition, the 3D local optimiser and a seed-000
// hill climb behind one call (the 3D twin of fit.h; the seed-004 evolution strategy comes later).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "csgfit/decompose3d.h"
#include "csgfit/evaluator.h"
#include "csgfit/fit.h"
#include "csgfit/tree3d.h"
#include "csgfit/voxel_grid.h"

namespace csgfit {

/// Everything a 3D fit takes besides the voxels.
struct FitOptions3D {
  double k = -1;               ///< size weight in voxels; < 0 means default_k3d(target)
  PrimitiveSet3D primitives = PrimitiveSet3D::matchable();
  double time_limit = 10;      ///< seconds of wall time for the whole fit
  int threads = 0;             ///< 0 = all cores
  std::uint64_t seed = 1;
  int max_stale = 600;         ///< perturbations without improvement before "converged"
};

/// k for a grid: 200 voxels per primitive per million voxels of the grid (the target's whole
/// box, margins included), at least 8. A primitive must then explain a piece of about 1/17 of
/// the grid's mean side cubed, which keeps the smallest kept feature at the same fraction of
/// the part's size at every resolution. (100 per million, the 2D default's rule in 3D, gave
/// 67 primitives on the InverseCSG CAD meshes where InverseCSG's programs have 61.)
double default_k3d(const VoxelGrid& target);

/// Fills the mismatch fields of `stats` (excess including the tree beyond the grid, uncovered,
/// primitives, k, score, IoU over a target of `target_voxels`) from one measurement.
void set_mismatch_stats(FitStats& stats, const Mismatch& mismatch, std::size_t target_voxels,
                        std::size_t primitives, double k);

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

/// The fit as JSON: schema "csgfit/1" with "dimension": 3 (lengths in the mesh's units):
/// {"schema", "dimension": 3, "units", "source", "grid": {"nx", "ny", "nz", "origin": [x, y, z],
/// "voxel_size"}, "tree", "stats"}. Operator nodes as in 2D ({"op", "children"}); a primitive is
/// {"type", "center": [x, y, z], "rotation": [w, x, y, z] (unit quaternion, local -> model),
/// "euler_deg": [a, b, c] (OpenSCAD rotate()), then its dimensions: box "size": [x, y, z];
/// sphere "r"; cylinder "r", "h"; cone "r1" (bottom, local z = -h/2), "r2", "h"; ellipsoid
/// "radii": [rx, ry, rz]; torus "R", "r"; prism "w", "h", "depth", "apex"}. Throws
/// InputError for a non-finite value.
/// `frame` is the rotation of the fitting grid (grid -> mesh coordinates; written as "frame":
/// [w, x, y, z]); the tree itself is always in mesh coordinates.
std::string to_json3d(const FitResult3D& result, const VoxelGrid& grid, const std::string& source,
                      const Quaternion& frame = {});

/// Whether `text` is a JSON document with "dimension": 3 (false for 2D or unparsable text).
bool is_json3d(const std::string& text);
/// Reads the tree of a document written by to_json3d (`source` gets its "source"). The
/// quaternion "rotation" is used (euler_deg only when it is absent); the grid and stats are
/// not read. Throws InputError naming the bad field and node.
Node3D from_json3d(const std::string& text, std::string* source = nullptr);

}  // namespace csgfit
