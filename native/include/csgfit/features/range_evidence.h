// What the views say about space: points seen on the part's surface, and points seen to be
// empty (in front of a return along its ray, or along a ray that returned nothing). A tree
// agrees with the views when its surface passes through the first and it leaves the second
// outside; the hidden rest is free, so hidden extents come out as small as the views allow.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/range_scan.h"

namespace csgfit {

struct RangeEvidence {
  std::vector<Vec3> surface;  ///< seen on the surface
  std::vector<Vec3> empty;    ///< seen to be outside the part
  /// Points of the part's box that no view sees, behind the surface from every camera (none
  /// when a scan has no camera): where the primitives' hidden volume is.
  std::vector<Vec3> hidden;
  /// Points half a tolerance behind seen returns, along the inward normal: inside the part
  /// unless it is thinner than that. What tells a solid from a skin with the same surface.
  std::vector<Vec3> behind;
  double tolerance = 0;       ///< how far a surface point may be from the tree's surface
  std::vector<RangeCamera> cameras;  ///< the views' cameras (scans without one add none)
};

/// Whether a face through `point` with outward normal `normal` turns its back on every camera
/// of `evidence` (by more than a few degrees: a grazing face may still be seen); false when
/// there is no camera.
bool faces_away_from_every_view(const RangeEvidence& evidence, const Vec3& point, const Vec3& normal);

/// Samples the evidence of `scans` (at most about `max_surface` surface points, spread evenly),
/// with surface tolerance `tolerance`. Scans with a camera give empty points along their rays
/// (in front of returns, every ray that returned nothing near the silhouette, and others through
/// the part's box as far as `max_surface` allows); scans without one give them along the outward
/// normals. Hidden points lie on a lattice over the part's box; behind points come with every
/// other surface point whose normal faces its view (not grazing, where normals blur).
RangeEvidence gather_evidence(const std::vector<RangeScan>& scans, double tolerance,
                              std::size_t max_surface);

}  // namespace csgfit
