// Hand-made parts that are (or are not) sweeps, inside [0, 32]^3 so that the OpenSCAD round
// trip's grid holds them: find_sweeps's tests, the .scad writer's and its round trip.
#pragma once

#include "csgfit/model/tree3d.h"

namespace csgfit::testing {

/// A 26 x 18 x 4 plate (z from 8 to 12) minus two round holes of radius 2.5 that reach beyond
/// it and a hexagonal one turned by 10 degrees: one linear sweep along z, 4 high.
inline Node3D plate_with_holes() {
  Primitive3D hex =
      Primitive3D::cylinder(16, 20, 10, 3, 4, Quaternion::from_axis_angle(0, 0, 1, 10));
  hex.sides = 6;
  return Node3D::op(NodeKind::Difference,
                    {Node3D::leaf(Primitive3D::box(16, 16, 10, 26, 18, 4)),
                     Node3D::leaf(Primitive3D::cylinder(8, 11, 10, 2.5, 8)),
                     Node3D::leaf(Primitive3D::cylinder(24, 11, 10, 2.5, 8)), Node3D::leaf(hex)});
}

/// A rounded plate, 26 x 18 x 4 with corners of radius 4 (z from 8 to 12; a rounded box of
/// sizes 18 x 26 turned by 90 degrees, so that the plane sees its y first), minus a round
/// hole and a slot (a stadium 8 x 3 turned by 30 degrees) that both reach beyond it: one
/// linear sweep along z, 4 high.
inline Node3D rounded_plate_with_slot() {
  return Node3D::op(
      NodeKind::Difference,
      {Node3D::leaf(Primitive3D::rounded_box(16, 16, 10, 18, 26, 4, 4,
                                             Quaternion::from_axis_angle(0, 0, 1, 90))),
       Node3D::leaf(Primitive3D::cylinder(9, 16, 10, 2.5, 8)),
       Node3D::leaf(Primitive3D::rounded_box(22, 16, 10, 8, 3, 6, 1.5,
                                             Quaternion::from_axis_angle(0, 0, 1, 30)))});
}

/// An L bracket: a 24 x 14 x 4 base (x from 4 to 28, z from 4 to 8) and a 4 x 14 x 22 wall on
/// its end (x from 4 to 8, up to z = 26), both 14 long in y: swept along y.
inline Node3D bracket() {
  return Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(16, 16, 6, 24, 14, 4)),
                                      Node3D::leaf(Primitive3D::box(6, 16, 15, 4, 14, 22))});
}

/// A bush (a cylinder of radius 9, 12 high, minus a coaxial one of radius 4 through it) with a
/// torus round its middle, all about the vertical line through (16, 16): one revolution.
inline Node3D turned_part() {
  const Node3D bush =
      Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::cylinder(16, 16, 16, 9, 12)),
                                        Node3D::leaf(Primitive3D::cylinder(16, 16, 16, 4, 16))});
  return Node3D::op(NodeKind::Union, {bush, Node3D::leaf(Primitive3D::torus(16, 16, 16, 9, 2))});
}

/// Two boxes side by side on z = 4, 4 and 8 high, of different depths: no sweep.
inline Node3D steps() {
  return Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(10, 16, 6, 12, 12, 4)),
                                      Node3D::leaf(Primitive3D::box(22, 16, 8, 12, 8, 8))});
}

}  // namespace csgfit::testing
