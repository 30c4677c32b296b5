// Interpolation of corresponding primitives, written once over the tree type.
#include "csgfit/model/interpolate.h"

#include <cmath>
#include <stdexcept>

namespace csgfit {

namespace {

double lerp(double a, double b, double t) { return a + (b - a) * t; }

template <typename P>
CsgNode<P> interpolate_node(const CsgNode<P>& a, const CsgNode<P>& b, double t) {
  if (a.kind != b.kind || a.children.size() != b.children.size())
    throw std::invalid_argument("the two trees of a morph differ in structure");
  if (a.is_leaf()) {
    if (a.primitive.kind != b.primitive.kind)
      throw std::invalid_argument("the two trees of a morph differ in a primitive's kind");
    return CsgNode<P>::leaf(interpolate(a.primitive, b.primitive, t));
  }
  std::vector<CsgNode<P>> kids;
  kids.reserve(a.children.size());
  for (std::size_t i = 0; i < a.children.size(); ++i)
    kids.push_back(interpolate_node(a.children[i], b.children[i], t));
  return CsgNode<P>::op(a.kind, std::move(kids));
}

// The equivalent of `to` nearest `from` in the direction asked, for a shape that repeats every
// `period` degrees.
double turned(double from, double to, double period, TurnDirection direction) {
  double d = std::fmod(to - from, period);
  if (d < 0) d += period;  // d in [0, period): the counter-clockwise turn
  switch (direction) {
    case TurnDirection::CounterClockwise: break;
    case TurnDirection::Clockwise:
      if (d > 0) d -= period;
      break;
    case TurnDirection::Shortest:
      if (d > period / 2) d -= period;
      break;
  }
  return from + d;
}

}  // namespace

TurnDirection turn_direction_from_string(const std::string& name) {
  if (name == "shortest") return TurnDirection::Shortest;
  if (name == "cw") return TurnDirection::Clockwise;
  if (name == "ccw") return TurnDirection::CounterClockwise;
  throw std::invalid_argument("unknown rotation direction '" + name + "' (expected shortest, cw or ccw)");
}

Primitive interpolate(const Primitive& a, const Primitive& b, double t) {
  Primitive p = a;
  p.cx = lerp(a.cx, b.cx, t);
  p.cy = lerp(a.cy, b.cy, t);
  p.w = lerp(a.w, b.w, t);
  p.h = lerp(a.h, b.h, t);
  p.angle = lerp(a.angle, b.angle, t);
  p.apex = lerp(a.apex, b.apex, t);
  return p;
}

void relative_turn(const Quaternion& a, const Quaternion& b, Vec3& axis, double& degrees) {
  const Quaternion a_inverse{a.w, -a.x, -a.y, -a.z};
  Quaternion r = b * a_inverse;
  if (r.w < 0) r = {-r.w, -r.x, -r.y, -r.z};  // the short way round
  const double s = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
  if (s < 1e-12) {
    axis = {0, 0, 1};
    degrees = 0;
    return;
  }
  axis = {r.x / s, r.y / s, r.z / s};
  degrees = 2 * std::atan2(s, std::min(1.0, r.w)) * 180.0 / M_PI;
}

Primitive3D interpolate(const Primitive3D& a, const Primitive3D& b, double t) {
  Primitive3D p = a;
  p.cx = lerp(a.cx, b.cx, t);
  p.cy = lerp(a.cy, b.cy, t);
  p.cz = lerp(a.cz, b.cz, t);
  for (int i = 0; i < 3; ++i) p.dims[i] = lerp(a.dims[i], b.dims[i], t);
  p.apex = lerp(a.apex, b.apex, t);
  p.corner = lerp(a.corner, b.corner, t);
  Vec3 axis;
  double degrees = 0;
  relative_turn(a.rotation, b.rotation, axis, degrees);
  p.rotation = Quaternion::from_axis_angle(axis[0], axis[1], axis[2], t * degrees) * a.rotation;
  return p;
}

Node interpolate(const Node& a, const Node& b, double t) { return interpolate_node(a, b, t); }
Node3D interpolate(const Node3D& a, const Node3D& b, double t) { return interpolate_node(a, b, t); }

void choose_turns(const Node& a, Node& b, TurnDirection direction) {
  const std::vector<const Primitive*> from = leaves(a);
  const std::vector<Primitive*> to = leaves(b);
  if (from.size() != to.size())
    throw std::invalid_argument("the two trees of a morph differ in structure");
  for (std::size_t i = 0; i < to.size(); ++i) {
    Primitive& p = *to[i];
    switch (p.kind) {
      case PrimitiveKind::Circle: p.angle = from[i]->angle; break;
      case PrimitiveKind::Rectangle:
      case PrimitiveKind::Ellipse: p.angle = turned(from[i]->angle, p.angle, 180, direction); break;
      case PrimitiveKind::Triangle: p.angle = turned(from[i]->angle, p.angle, 360, direction); break;
    }
  }
}

}  // namespace csgfit
