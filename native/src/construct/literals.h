// Internal to construct/: the halfspaces of the construction (Shapiro and Vossler's boundary
// halfspaces): one per surface of the mesh, and the separating ones that fillets and round
// ends need (the planes through a cylinder's axis, through a ball's or a torus's centre, the
// cylinder of a torus's core circle), without which some cells of a rounded part could not be
// told apart.
#pragma once

#include <vector>

#include "csgfit/features/mesh_surfaces.h"
#include "csgfit/model/primitive3d.h"

namespace csgfit::construct {

/// One halfspace: a plane's inner side (n . x <= offset) or a bounded solid reaching across the
/// whole domain (a cylinder or cone as long as the domain is wide, a ball, a torus).
struct Literal {
  bool plane = true;
  Vec3 normal{0, 0, 1};
  double offset = 0;
  Primitive3D solid;
  /// No face of the mesh lies on it: it only separates cells.
  bool separating = false;

  bool contains(const Vec3& p) const;
};

/// The construction's halfspaces over `domain` (the box every sample lies in), each once.
/// Surfaces read as regular polygons of at most `max_polygon_sides` sides stay polygons; rounder
/// ones become round primitives of the same area.
std::vector<Literal> literals_of(const MeshSurfaces& surfaces, const Bounds3& domain,
                                 int max_polygon_sides, const PrimitiveSet3D& kinds);

/// Round stand-in for a regular polygon of `sides` (0: a true circle) too fine to write as one:
/// the radius of the circle of the same area.
double area_radius(double circumradius, int sides);

/// Whether a unit vector lies along a model axis (the fitting frame's): which one, or -1.
int model_axis(const Vec3& direction);

/// A rotation taking local z onto `z` and local x onto (the part across z of) `x`.
Quaternion frame_along(const Vec3& z, const Vec3& x);

}  // namespace csgfit::construct
