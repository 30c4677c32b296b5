// Internal: the geometry of the RoundedBox, kept apart from the older kinds of primitive3d.cpp.
// Local coordinates throughout (Primitive3D::to_local).
#pragma once

#include "csgfit/model/primitive3d.h"
#include "model/interval.h"

namespace csgfit::rounded_box {

/// Exact signed distance in the local xy plane from (x, y) to the rounded rectangle (negative
/// inside).
double section_distance(const Primitive3D& p, double x, double y);
/// |z| <= sz/2 and (x, y) within the rounded rectangle.
bool contains(const Primitive3D& p, const Vec3& local);
/// The rounded rectangle's area times the height.
double volume(const Primitive3D& p);
/// Tight bounds in model coordinates: the core box's (the box of the corner centres, full
/// height) plus the corner circle's, whose plane is the local xy.
Bounds3 bounds(const Primitive3D& p);
/// The s where u s + b lies inside p (one interval: the solid is convex), or an empty one.
interval::Interval line_interval(const Primitive3D& p, const Vec3& u, const Vec3& b);

}  // namespace csgfit::rounded_box
