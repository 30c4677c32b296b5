// Solid voxels of a triangle mesh, robust for open, non-manifold, self-intersecting and badly
// oriented meshes (docs/INPUTS_3D.md).
#pragma once

#include <array>
#include <cstddef>

#include "csgfit/model/mesh.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// Voxelisation settings.
struct VoxelizeOptions {
  /// Voxels along the longest side of the bounding box (used when voxel_size <= 0).
  int resolution = 96;
  /// Explicit voxel edge length in model units; overrides resolution when > 0.
  double voxel_size = 0;
  /// Empty voxels added on every side of the bounding box.
  int margin = 1;
  /// Moves the lattice by this fraction of a voxel along x, y and z (0 <= shift < 1): a second,
  /// staggered sampling of the same part that TreeEvaluator3D can count beside the first.
  double lattice_shift = 0;
  /// When set, the lattice covers this box as well as the mesh's (two meshes voxelised with the
  /// same box and voxel size share one lattice, as a morph needs).
  bool cover_box = false;
  std::array<double, 3> box_lo{}, box_hi{};
  /// Grids with more voxels are refused (InputError).
  std::size_t max_voxels = std::size_t{1} << 27;
  /// Work budget for the exact generalised winding number (voxels x triangles) where the
  /// six ray votes do not agree; beyond it the vote decides.
  double winding_budget = 4e8;
};

/// How a voxelisation went, for diagnostics and tests.
struct VoxelizeStats {
  std::size_t ambiguous_voxels = 0;     ///< ray votes split (2, 3 or 4 of 6)
  std::size_t winding_evaluations = 0;  ///< voxels decided by the winding number
  std::size_t orientation_flips = 0;    ///< triangles flipped by repair_orientation
  double seconds = 0;
};

/// The voxel edge `csgfit mesh` uses when no resolution is given: about 11 voxels across the
/// part's mean wall thickness 2V/A (a voxel fit is exact only to half a voxel per face), at least
/// the voxels of 96 along the longest side (more for thin, elongated boxes), within 256 along
/// the longest side and 160^3 voxels in all. 0 when the report has no extent.
double auto_voxel_size(const MeshReport& report);

/// Solid voxels of a mesh: voxel centres inside the mesh. Inside/outside is decided per voxel
/// centre by six rays (both directions along x, y and z); each ray's signed crossing count
/// (the winding number along it, non-zero rule) is one vote, computed for a whole grid row at
/// once with a watertight edge rule. Unanimous or 5-of-6 votes decide; split votes fall back to
/// the generalised winding number |w| >= 1/2 (Jacobson et al. 2013). Orientation is repaired
/// first, so inverted or inconsistently oriented meshes give the same solid, and overlapping
/// closed parts give their union. Throws InputError for an empty mesh, non-finite coordinates or
/// a grid over max_voxels.
VoxelGrid voxelize(const TriangleMesh& mesh, const VoxelizeOptions& options = {},
                   VoxelizeStats* stats = nullptr);

/// Generalised winding number of the mesh at point p (sum of signed solid angles / 4 pi):
/// 1 inside a closed outward-oriented mesh, 0 outside, fractional near holes.
double winding_number(const TriangleMesh& mesh, const std::array<double, 3>& p);

}  // namespace csgfit
