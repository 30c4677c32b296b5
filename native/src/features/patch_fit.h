// Internal to features/: distances to a detected surface, its least-squares polish and the
// convexity of the solid behind it (seed 002, Sec. 3.3).
#pragma once

#include <vector>

#include "csgfit/features/surface_detect.h"

namespace csgfit {

/// Signed distance of p to the patch's surface (positive on the side its parameters call
/// outside: along a plane's normal, away from a sphere's centre or an axis).
double surface_distance(const SurfacePatch& patch, const Vec3& p);
/// The surface's unit normal at (the point of the surface nearest) p, pointing away from the
/// sphere's centre, the axis or the torus's core circle; a plane's own normal.
Vec3 surface_normal(const SurfacePatch& patch, const Vec3& p);
/// Refits the parameters to the patch's points by least squares: a plane through the centroid
/// with the normal of least variance (oriented along the points' normals), a sphere
/// algebraically, a cylinder's axis from its normals and its circle in the axis's plane.
void polish_patch(SurfacePatch& patch, const std::vector<Vec3>& points,
                  const std::vector<Vec3>& normals);
/// Whether most of the patch's point normals agree with surface_normal: the solid is on the
/// concave side of the surface (a convex bump, seed 002's positive primitive).
bool is_convex(const SurfacePatch& patch, const std::vector<Vec3>& points,
               const std::vector<Vec3>& normals);
/// A circle about `axis` (unit) through points projected across it: the algebraic fit, then
/// Gauss-Newton on the geometric distances. `centre` is on the axis line through it, in the
/// plane across the axis through `origin`.
struct AxisCircle {
  Vec3 centre{0, 0, 0};
  double radius = 0;
  double max_error = 0;  ///< largest distance of a point's projection from the circle
  bool ok = false;
};
AxisCircle fit_axis_circle(const std::vector<Vec3>& points, const Vec3& origin, const Vec3& axis);

double patch_rms(const SurfacePatch& patch, const std::vector<Vec3>& points);

}  // namespace csgfit
