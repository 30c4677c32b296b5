// Internal: the geometry of seed 004's NURBS terminal (Primitive3D::Nurbs), kept apart from the
// closed-form kinds of primitive3d.cpp. Local coordinates throughout (Primitive3D::to_local).
#pragma once

#include "csgfit/model/primitive3d.h"

namespace csgfit::nurbs {

/// 0 <= z <= S(x, y) over the rectangle.
bool contains(const Primitive3D& p, const Vec3& local);
/// The larger of the distance to the prism over the rectangle standing on the floor and the
/// vertical gap z - S(x, y) divided by sqrt(1 + |grad S|^2): exact on the floor and the walls,
/// first-order accurate at the top face, the right sign everywhere.
double signed_distance(const Primitive3D& p, const Vec3& local);
/// The integral of max(S, 0) over the rectangle (Gauss-Legendre per knot span).
double volume(const Primitive3D& p);
/// dims from the patch: {sx, sy, highest control height}.
Vec3 dims_of(const BSplineSurface& patch);
/// Whether two patches are the same surface (degrees, knots, net).
bool same_patch(const BSplineSurface* a, const BSplineSurface* b);

}  // namespace csgfit::nurbs
