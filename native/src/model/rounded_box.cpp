// The RoundedBox: the rectangle of its corner centres, |x| <= sx/2 - corner and
// |y| <= sy/2 - corner (its "core"), grown by the corner radius in the local xy plane and
// extruded over |z| <= sz/2. Growing a rectangle by a disc is what makes every query exact and
// cheap: the distance is the core's distance less the radius.
#include "model/rounded_box.h"

#include <algorithm>
#include <cmath>

namespace csgfit::rounded_box {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Half the core's sides.
double core_x(const Primitive3D& p) { return p.dims[0] / 2 - p.corner; }
double core_y(const Primitive3D& p) { return p.dims[1] / 2 - p.corner; }

// Narrows `iv` to the s where (u0 s + b0, u1 s + b1) lies within r of (cx, cy). The caller
// passes a line not parallel to local z (u0, u1 not both ~0).
interval::Interval disc_interval(double u0, double u1, double b0, double b1, double cx,
                                 double cy, double r) {
  const double px = b0 - cx, py = b1 - cy;
  const double a = u0 * u0 + u1 * u1, half_b = u0 * px + u1 * py, c = px * px + py * py - r * r;
  const double disc = half_b * half_b - a * c;
  if (disc < 0) return {1, 0};
  // Cancellation-free roots: q / a and c / q.
  const double q = -(half_b + std::copysign(std::sqrt(disc), half_b));
  if (q == 0) return {0, 0};
  const double s0 = q / a, s1 = c / q;
  return {std::min(s0, s1), std::max(s0, s1)};
}

}  // namespace

double section_distance(const Primitive3D& p, double x, double y) {
  const double qx = std::fabs(x) - core_x(p), qy = std::fabs(y) - core_y(p);
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0);
  return std::sqrt(ox * ox + oy * oy) + std::min(std::max(qx, qy), 0.0) - p.corner;
}

bool contains(const Primitive3D& p, const Vec3& l) {
  if (std::fabs(l[2]) > p.dims[2] / 2) return false;
  const double qx = std::fabs(l[0]) - core_x(p), qy = std::fabs(l[1]) - core_y(p);
  // Across the core's width, then its height, the section is a slab; beyond both, a disc.
  if (qx <= 0) return std::fabs(l[1]) <= p.dims[1] / 2;
  if (qy <= 0) return std::fabs(l[0]) <= p.dims[0] / 2;
  return qx * qx + qy * qy <= p.corner * p.corner;
}

double volume(const Primitive3D& p) {
  // The rectangle less its four corner squares, plus the four quarter discs.
  const double r = p.corner;
  return p.dims[2] * (p.dims[0] * p.dims[1] - (4 - kPi) * r * r);
}

Bounds3 bounds(const Primitive3D& p) {
  const Mat3 m = p.rotation.matrix();
  const Vec3 c{p.cx, p.cy, p.cz};
  const double core[3] = {core_x(p), core_y(p), p.dims[2] / 2};
  Bounds3 out;
  for (int i = 0; i < 3; ++i) {
    double e = p.corner * std::sqrt(std::max(0.0, 1 - m[i][2] * m[i][2]));
    for (int j = 0; j < 3; ++j) e += std::fabs(m[i][j]) * core[j];
    out.lo[i] = c[i] - e;
    out.hi[i] = c[i] + e;
  }
  return out;
}

interval::Interval line_interval(const Primitive3D& p, const Vec3& u, const Vec3& b) {
  interval::Interval slab;
  interval::clip_linear(slab, u[2], b[2], -p.dims[2] / 2, p.dims[2] / 2);
  if (slab.empty()) return slab;
  const double a = p.dims[0] / 2, h = p.dims[1] / 2, ca = core_x(p), ch = core_y(p);
  // A line along local z is inside the section everywhere or nowhere.
  if (std::fabs(u[0]) < 1e-12 && std::fabs(u[1]) < 1e-12)
    return contains(p, {b[0], b[1], 0}) ? slab : interval::Interval{1, 0};
  // The section is the union of the two slabs crossing at the core and the four discs at its
  // corners; being convex, its interval on the line is the hull of theirs.
  interval::Interval wide, tall, hull{1, 0};
  interval::clip_linear(wide, u[0], b[0], -a, a);
  interval::clip_linear(wide, u[1], b[1], -ch, ch);
  interval::clip_linear(tall, u[0], b[0], -ca, ca);
  interval::clip_linear(tall, u[1], b[1], -h, h);
  auto join = [&hull](const interval::Interval& iv) {
    if (iv.empty()) return;
    if (hull.empty()) hull = iv;
    hull = {std::min(hull.lo, iv.lo), std::max(hull.hi, iv.hi)};
  };
  join(wide);
  join(tall);
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) join(disc_interval(u[0], u[1], b[0], b[1], sx * ca, sy * ch, p.corner));
  return {std::max(hull.lo, slab.lo), std::min(hull.hi, slab.hi)};
}

}  // namespace csgfit::rounded_box
