// A tree seen again by a range sensor: the depth along each pixel's ray to the tree's first
// surface, by sphere tracing its signed distance (a lower bound of the true distance, so the
// march never steps through a surface).
#pragma once

#include <vector>

#include "csgfit/model/range_scan.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// Depth (camera z, as the sensor measures it) of the tree at every pixel of `camera`, row by
/// row; 0 where the ray misses. `tolerance` is the surface thickness of the march.
std::vector<double> tree_depth_map(const Node3D& tree, const RangeCamera& camera,
                                   double tolerance);

/// How a depth map of the tree agrees with what the sensor saw: silhouette IoU of returns and
/// hits, and the mean |depth difference| over pixels both see.
struct DepthAgreement {
  double silhouette_iou = 0;
  double mean_depth_error = 0;
  std::size_t seen = 0, hit = 0, both = 0;
};

/// Compares `tree_depth` (tree_depth_map) with the scan's own depths (its points projected).
DepthAgreement compare_depth(const RangeScan& scan, const std::vector<double>& tree_depth);

}  // namespace csgfit
