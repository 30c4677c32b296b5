// Morphing between two structurally identical trees (seed 000, "Application to geometric
// morphing"): corresponding primitives interpolated, and the direction each one turns.
#pragma once

#include <string>

#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// Which way a 2D primitive turns from its angle in A to its angle in B.
enum class TurnDirection { Shortest, Clockwise, CounterClockwise };

/// Parses "shortest", "cw" or "ccw"; throws std::invalid_argument otherwise.
TurnDirection turn_direction_from_string(const std::string& name);

/// The primitive at `t` (0 = a, 1 = b): every number linear in t, the angle included (B's angle
/// is already the one the turn ends at, see choose_turns). Kinds must match.
Primitive interpolate(const Primitive& a, const Primitive& b, double t);
/// 3D: centre and dimensions linear, the rotation along the arc from a's to b's
/// (q(t) = (q_b q_a^-1)^t q_a, the .scad writes it as one rotate(a, v) after a's rotation).
Primitive3D interpolate(const Primitive3D& a, const Primitive3D& b, double t);

/// The tree at `t`. Throws std::invalid_argument when a and b differ in structure or in a
/// primitive's kind.
Node interpolate(const Node& a, const Node& b, double t);
Node3D interpolate(const Node3D& a, const Node3D& b, double t);

/// Sets every angle of `b` to the one its turn from `a` ends at: the nearest equivalent angle
/// of the primitive's symmetry (180 degrees for rectangles and ellipses, 360 for triangles) in
/// the direction asked; a circle does not turn. `b` keeps its shape; only the morph changes.
void choose_turns(const Node& a, Node& b, TurnDirection direction);
/// The axis (unit) and angle in degrees, in [0, 180], that turn rotation `a` into `b` in the
/// model frame: b = R(axis, angle) a, the short way (3D turns always take it). No turn gives
/// angle 0 and axis z.
void relative_turn(const Quaternion& a, const Quaternion& b, Vec3& axis, double& degrees);

}  // namespace csgfit
