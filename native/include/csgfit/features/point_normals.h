// Surface normals of the points a range sensor saw: from the image neighbourhood of an
// organised scan, or by principal components of the nearest neighbours of an unorganised cloud,
// turned to point out of the part (towards the sensor). What the surface detector needs.
#pragma once

#include <optional>

#include "csgfit/model/quaternion.h"
#include "csgfit/model/range_scan.h"

namespace csgfit {

struct PointNormalOptions {
  /// Organised scans: the plane is fitted to the (2r + 1) x (2r + 1) pixels around each one.
  int window_radius = 2;
  /// Organised scans: a neighbour farther from the pixel's point than this many pixel
  /// footprints per pixel step lies across a depth discontinuity (another surface). Four
  /// keeps surfaces up to 75 degrees from the view together.
  double max_jump = 4;
  /// Unorganised clouds: the neighbours whose principal components give a normal.
  int neighbours = 14;
  /// Unorganised clouds: a point whose mean distance to its neighbours is over this many times
  /// the cloud's average spacing is an outlier.
  double outlier_spacing = 8;
  /// Organised scans without a camera: the direction a sensor looked along, when known, to
  /// turn the normals towards it; without it they point away from the points' centroid.
  std::optional<Vec3> view_direction;
};

/// Gives every point of `scan` a unit normal pointing out of the part, keeping the normals the
/// file gave (normalised) and estimating them when scan.normals is empty: organised scans from
/// the image neighbourhood (not across depth discontinuities), turned towards the camera;
/// unorganised clouds from their nearest neighbours, oriented consistently along a minimum
/// spanning tree and outwards. Points where no normal can be had (isolated, degenerate
/// neighbourhood, a zero or NaN normal in the file) are dropped and counted in
/// scan.dropped_outliers; the rest keep their order, with `pixel` aligned.
void complete_normals(RangeScan& scan, const PointNormalOptions& options = {});

}  // namespace csgfit
