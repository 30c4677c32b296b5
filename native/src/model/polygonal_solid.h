// Internal: the geometry of a polygonal Cylinder or Cone (Primitive3D::sides >= 3), kept apart
// from the round kinds of primitive3d.cpp. Local coordinates throughout (Primitive3D::to_local).
#pragma once

#include "csgfit/model/primitive3d.h"
#include "model/interval.h"

namespace csgfit::polygonal {

/// Exact signed distance in the plane from (x, y) to the regular n-gon of circumradius r with
/// vertex 0 on +x (negative inside).
double section_distance(int n, double r, double x, double y);
/// |z| <= h/2 and (x, y) within the polygon of the circumradius at z.
bool contains(const Primitive3D& p, const Vec3& local);
/// The largest signed distance to the planes of the faces (the sides and both ends); exact for
/// the prism only inside (primitive3d.cpp composes its exact one from section_distance).
double face_plane_distance(const Primitive3D& p, const Vec3& local);
/// The polygon's area times the height; the frustum's by the prismatoid formula.
double volume(const Primitive3D& p);
/// The bounds of the end polygons' vertices, in model coordinates.
Bounds3 bounds(const Primitive3D& p);
/// Narrows `iv` to the s where u s + b lies inside p: the z slab and one half-space per side.
void clip_line(const Primitive3D& p, const Vec3& u, const Vec3& b, interval::Interval& iv);

}  // namespace csgfit::polygonal
