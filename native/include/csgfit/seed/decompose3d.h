// Seed 003 in 3D (Chirehdast & Papalambros, "3D extensions"): moment-based matching of voxel
// regions to primitives, and the recursive bounding-box difference with the heuristic split.
#pragma once

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>

#include "csgfit/features/features3d.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {


/// A primitive matched to a region, with how well it fits.
struct RegionMatch3D {
  Primitive3D primitive;
  std::size_t mismatch = 0;  ///< voxels where the primitive and the region differ
  /// Seed 003's volume check (eq. 15) for the block: the product of the moment sizes over
  /// the region's volume (1 for an exact block).
  double block_volume_ratio = 0;
};

/// Matches a voxel region to the primitive library by its volume, centroid and principal
/// moments (seed 003, eqs. 8-15 and their analogues): block sizes sqrt(12 lambda_i) along the
/// principal axes; ellipsoid semi-axes sqrt(5 lambda_i) (sphere: their mean); a cylinder along
/// each principal axis in turn (r = 2 sqrt(lambda_perp), h = sqrt(12 lambda_axis)); cones and
/// frusta with a few radius ratios, both ways along each axis; triangular blocks extruded along
/// each axis with the triangle family of the cross-section's moments. The best few by voxel
/// mismatch are refined by the 3D local optimiser against the region; the smallest mismatch
/// wins (ties go to the simpler kind). Nothing if no kind is allowed or the region is empty.
std::optional<RegionMatch3D> match_region3d(const VoxelGrid& region, PrimitiveSet3D allowed);

struct DecomposeOptions3D {
  PrimitiveSet3D primitives = PrimitiveSet3D::matchable();
  double k = 100;       ///< size weight: a part is kept when it scores better than its voxels
  int max_depth = 12;   ///< recursion bound (the split heuristic alone already bounds it)
  int connectivity = 6; ///< of solid regions; holes use dual_connectivity() of it
  /// Seconds after which only seed 003's own steps are taken (the matched-primitive
  /// refinement, which roughly doubles the work, is skipped); <= 0: no limit.
  double time_limit = 0;
  /// When set and true, the decomposition winds up as it does past time_limit (every region
  /// left gets its box or nothing), so a cancelled fit still ends with a valid tree, soon.
  const std::atomic<bool>* cancel = nullptr;
};

/// The seed-003 tree of `target`: union over the solid's components of
/// region(R) = best of { matched primitive, box(R) - union(region(S) for the complementary
/// sub-regions S of R in its box) } by the score mismatch + k x primitives, where a sub-region
/// may also be left out (it costs its voxels). Sub-regions of no more than k voxels are left
/// out. Where a sub-region's box equals its parent's (seed 003, Figure 15) it is split in two
/// perpendicular to its longest side and the halves are solved separately, so every recursion
/// shrinks a box and the algorithm always terminates. Beyond the seed, a matched primitive
/// that is not exact is also tried with its own errors decomposed (primitive minus the
/// sub-regions it covers wrongly, plus those it misses), which keeps rotated parts rotated. Boxes must be allowed. Throws
/// std::invalid_argument if the target is empty.
Node3D decompose3d(const VoxelGrid& target, const DecomposeOptions3D& options);

}  // namespace csgfit
