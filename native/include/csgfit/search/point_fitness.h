// Seed 004's fitness of a CSG tree against a scanned point cloud (Sec. 2.2): per point
//   F_p = w_d / (1 + d / scale) + w_abn ABN + w_ct CT - N / c,
// averaged over the points, higher is better. d is the distance from the point to the tree
// along z for a scan seen from above (the seed's 2.5D setting, its z-ray), or to the tree's
// surface for a scan all around; ABN is max(0, n . n_tree); CT is 1 where the point's
// curvature type (computed once, from the cloud) matches the tree's there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/features/point_curvature.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// How the part was scanned: from above (2.5D: the solid fills each column from the floor up
/// to the scanned surface) or all around (a closed surface).
enum class ScanKind { Top, All };

/// The cloud as the fitness reads it, every per-point quantity computed once.
struct PointTarget {
  ScanKind scan = ScanKind::All;
  std::vector<Vec3> points, normals;        ///< unit normals, out of the part
  std::vector<CurvatureType> curvature;     ///< one per point
  /// Top scans: where the scanner saw no part, it saw the table; points at the floor there
  /// say the tree must have nothing above it (the seed's die covers its table; a part that does
  /// not would otherwise leave the search free to fill the gaps).
  std::vector<Vec3> floor_samples;
  double floor = 0;       ///< top scans: the table's height
  double top = 0;         ///< the highest point's z (or the floor, if higher)
  double diagonal = 1;    ///< of the points' bounding box
  double spacing = 1;     ///< mean distance to the nearest neighbour
};

/// The weights of F_p; scale turns d into the seed's Delta (a fraction of the diagonal).
struct FitnessWeights {
  double distance = 1.0, normals = 0.3, curvature = 0.2;
  double scale = 0.004;   ///< d / (scale * diagonal) is the seed's Delta
  double node_cost = 1.0 / 250;  ///< 1 / c, per node of the tree
};

/// The averaged terms of one evaluation (each in [0, 1]), and F itself.
struct FitnessTerms {
  double distance = 0, normals = 0, curvature = 0, floor = 0;
  double mean_distance = 0;  ///< mean d in model units (for reports)
  std::size_t nodes = 0;
  double fitness = 0;
};

/// Builds the target: curvature types from the normals of each point's k nearest neighbours,
/// the spacing, and for a top scan the floor samples on a grid over the points' x-y box where
/// no point lies within three spacings. Points and normals must be of equal, non-zero size.
PointTarget make_point_target(std::vector<Vec3> points, std::vector<Vec3> normals, ScanKind scan,
                              double floor);

/// F of the tree over the points with the given indices (all when `subset` is empty), the
/// floor samples weighted like points.
FitnessTerms point_fitness(const Node3D& tree, const PointTarget& target,
                           const FitnessWeights& weights, const std::vector<std::size_t>& subset = {});

/// The seed's z-ray: the highest z at which the vertical line through (x, y) meets the tree,
/// or -infinity when it misses (exact intervals per primitive, combined by the tree's
/// operators).
double column_top(const Node3D& tree, double x, double y);

/// The tree's curvature type at a surface point: that of the primitive whose surface is
/// nearest, flipped when the primitive is subtracted (a convex sphere cut out is concave).
CurvatureType tree_curvature(const Node3D& tree, const Vec3& point);

}  // namespace csgfit
