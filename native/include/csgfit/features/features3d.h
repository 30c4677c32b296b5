// Features of a voxel grid the 3D seeds and search use: connected regions, volume moments with
// principal axes, and cropping (the 3D twin of features.h).
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/primitive3d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// A connected set of voxels. `mask` is cropped to the region's bounding box but keeps the
/// parent's placement (its origin is moved, the voxel size is the same), so primitives in model
/// coordinates rasterise on it directly. lo/hi are inclusive voxel indices of the bounding box
/// in the grid the region was found in.
struct Region3D {
  VoxelGrid mask;
  int lo[3] = {0, 0, 0}, hi[3] = {-1, -1, -1};
  std::size_t volume = 0;
};

/// The sub-grid of voxels [lo, hi] (inclusive) of `grid`, widened by `pad` empty voxels on
/// every side, with the matching placement. Indices outside `grid` read as empty.
VoxelGrid crop(const VoxelGrid& grid, const int lo[3], const int hi[3], int pad = 0);

/// Connected components of the set voxels of `mask`. connectivity is 6 (faces), 18 (faces and
/// edges) or 26 (faces, edges and corners). Components come in scan order (x fastest, then y,
/// then z of their first voxel), so the result is deterministic. Throws std::invalid_argument
/// on another connectivity.
std::vector<Region3D> connected_regions3d(const VoxelGrid& mask, int connectivity);

/// The connectivity that pairs with `connectivity` for the complement: 6 <-> 26, 18 -> 6.
/// Seed 003 uses faces for objects and edges (18) for holes; we pair 6 with 26, the standard
/// pair of digital topology for which a 6-connected solid and its 26-connected complement
/// separate each other exactly as in the continuous case: a gap that only a corner closes
/// is then one hole, not two, which gives fewer and larger sub-regions.
int dual_connectivity(int connectivity);

/// Volume moments of a set of voxels in model coordinates, each voxel a solid cube of edge s
/// (so it adds s^2/12 to each axis' variance).
struct Moments3D {
  double volume = 0;            ///< in model units^3
  std::size_t voxels = 0;
  Vec3 centroid{0, 0, 0};
  Mat3 covariance{};            ///< central second moments / volume
  Vec3 variances{0, 0, 0};      ///< principal variances, descending
  Mat3 axes{};                  ///< columns: unit principal axes, right-handed (det +1)
};
Moments3D compute_moments3d(const VoxelGrid& mask);


/// Voxels of `mask` that have all six face neighbours in `mask` (one step of erosion; outside
/// the grid counts as empty).
VoxelGrid erode6(const VoxelGrid& mask);

}  // namespace csgfit
