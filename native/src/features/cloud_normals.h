// Normals of an unorganised point cloud (CGAL's point set processing), kept apart from the
// organised scans' so that only this file compiles CGAL's templates.
#pragma once

#include <vector>

#include "csgfit/model/quaternion.h"

namespace csgfit::features_detail {

/// One unit normal per point, NaN for the outliers (mean distance to the `k` nearest over
/// `outlier_spacing` times the average spacing) and where there are too few points: the
/// principal component of least variance of the k nearest neighbours, oriented along a
/// minimum spanning tree from the highest point (whose normal points up) and, in parts of the
/// cloud the tree does not reach, away from the centroid.
std::vector<Vec3> cloud_normals(const std::vector<Vec3>& points, int k, double outlier_spacing);

}  // namespace csgfit::features_detail
