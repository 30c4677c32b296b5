// Rounded rectangles read off their corner arcs: the outline designers draw most (hull of four
// circles, offset(r) square), and slots (a stadium: two half circles). Each is one halfspace of
// the construction, a rounded box as long as the part is wide, so that a plate or a slot is one
// product (the rounded box and its caps) rather than two boxes and four cylinders.
#include "rounded_rectangles.h"

#include <algorithm>
#include <cmath>

#include "model/linalg.h"
#include "tuning.h"

namespace csgfit::construct {

namespace {

using namespace linalg;

// One arc of a cylinder surface, seen across its axis.
struct Arc {
  Vec3 centre{0, 0, 0}, axis{0, 0, 1};
  Vec3 outward{1, 0, 0};  // from the centre to the middle of the arc's faces
  double radius = 0, sweep = 0;
  int sides = 0;  // of the polygon the arc is part of (0: round)
  bool convex = true;
};

Vec3 vertex(const TriangleMesh& m, int v) { return {m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}; }

std::vector<Arc> arcs_of(const MeshSurfaces& ms) {
  std::vector<Arc> out;
  for (const MeshSurface& s : ms.surfaces) {
    if (s.shape.kind != SurfaceKind::Cylinder || s.sweep >= kWholeSweep || s.sweep < kLeastCornerSweep) continue;
    Arc a;
    a.axis = s.shape.axis, a.radius = s.shape.radius, a.sweep = s.sweep, a.convex = s.shape.convex;
    a.sides = s.sides;
    a.centre = s.shape.point;
    Vec3 mean{0, 0, 0};
    for (int t : s.triangles)
      for (int v : ms.mesh.triangles[t]) mean = add(mean, reject(sub(vertex(ms.mesh, v), a.centre), a.axis));
    a.outward = normalized(mean);
    if (norm(a.outward) < 0.5) continue;
    out.push_back(a);
  }
  return out;
}

bool alike(const Arc& a, const Arc& b, double tol) {
  return a.convex == b.convex && std::abs(a.radius - b.radius) <= tol && norm(cross(a.axis, b.axis)) < 1e-6;
}

// A rounded rectangle across `axis`: corner centres at s0..s1 along u and t0..t1 along v.
struct Outline {
  Vec3 axis, u, v, origin;  // origin: a point on the axis plane the s, t are measured from
  double s0, s1, t0, t1, radius;
  int sides;
};

// Whether an arc is the corner of the outline its position asks for (quarter or half arcs
// pointing out of the outline there).
bool corner_of(const Outline& o, const Arc& a, double tol) {
  const Vec3 d = reject(sub(a.centre, o.origin), o.axis);
  const double s = dot(d, o.u), t = dot(d, o.v);
  const bool at_s = std::abs(s - o.s0) <= tol || std::abs(s - o.s1) <= tol;
  const bool at_t = std::abs(t - o.t0) <= tol || std::abs(t - o.t1) <= tol;
  if (!at_s || !at_t) return false;
  const double ws = o.s1 - o.s0 > tol ? (s > 0.5 * (o.s0 + o.s1) ? 1 : -1) : 0;
  const double wt = o.t1 - o.t0 > tol ? (t > 0.5 * (o.t0 + o.t1) ? 1 : -1) : 0;
  const Vec3 want = normalized(add(scale(o.u, ws), scale(o.v, wt)));
  return norm(want) > 0.5 ? dot(want, a.outward) > kCornerFacing : true;
}

// The outline of arcs a and b as diagonal corners (or a slot's two ends), when the arcs its
// other corners need are there too.
bool outline_of(const std::vector<Arc>& arcs, std::size_t i, std::size_t j, double tol, Outline& o) {
  const Arc &a = arcs[i], &b = arcs[j];
  const Vec3 apart = reject(sub(b.centre, a.centre), a.axis);
  if (norm(apart) <= tol || dot(a.outward, b.outward) > -kCornerFacing) return false;
  o.axis = a.axis, o.radius = a.radius, o.sides = a.sides, o.origin = a.centre;
  if (a.sweep > kHalfSweep) {
    // A slot: two half circles facing apart along the line between them.
    o.u = normalized(apart);
    if (dot(o.u, b.outward) < kCornerFacing) return false;
    o.v = cross(o.axis, o.u);
    o.s0 = 0, o.s1 = norm(apart), o.t0 = o.t1 = 0;
    return b.sweep > kHalfSweep;
  }
  // Diagonal corners: their outward directions are the outline's diagonals.
  o.u = normalized(add(b.outward, cross(a.axis, b.outward)));
  o.v = cross(o.axis, o.u);
  const double s = dot(apart, o.u), t = dot(apart, o.v);
  o.s0 = std::min(0.0, s), o.s1 = std::max(0.0, s), o.t0 = std::min(0.0, t), o.t1 = std::max(0.0, t);
  if (o.s1 - o.s0 <= tol || o.t1 - o.t0 <= tol) return false;
  for (const double cs : {o.s0, o.s1})
    for (const double ct : {o.t0, o.t1}) {
      bool found = false;
      for (const Arc& c : arcs) {
        const Vec3 d = reject(sub(c.centre, o.origin), o.axis);
        found = found || (alike(c, a, tol) && std::abs(dot(d, o.u) - cs) <= tol && std::abs(dot(d, o.v) - ct) <= tol &&
                          corner_of(o, c, tol));
      }
      if (!found) return false;
    }
  return true;
}

Literal outline_literal(const Outline& o, const Bounds3& domain) {
  // The outline's middle: the corner centres' mean, on the axis line nearest the domain's.
  const Vec3 mid2d = scale(add(scale(o.u, o.s0 + o.s1), scale(o.v, o.t0 + o.t1)), 0.5);
  const Vec3 box_centre = scale(add(domain.lo, domain.hi), 0.5);
  Vec3 c = add(o.origin, mid2d);
  c = add(c, scale(o.axis, dot(sub(box_centre, c), o.axis)));
  // One frame for one outline, whichever pair of corners found it: local x along the longer
  // side, pointing where its largest component is positive.
  const double along_u = o.s1 - o.s0, along_v = o.t1 - o.t0;
  Vec3 x = along_u >= along_v ? o.u : o.v;
  int big = 0;
  for (int k = 1; k < 3; ++k) big = std::abs(x[k]) > std::abs(x[big]) ? k : big;
  if (x[big] < 0) x = scale(x, -1);
  // The sides lie on the outline; the corners, polygons with their vertices on the arc, are
  // rounded to the circle of their area, as a fine polygonal cylinder is.
  Literal l;
  l.plane = false;
  l.solid = Primitive3D::rounded_box(c[0], c[1], c[2], std::max(along_u, along_v) + 2 * o.radius,
                                     std::min(along_u, along_v) + 2 * o.radius,
                                     2 * norm(sub(domain.hi, domain.lo)), area_radius(o.radius, o.sides),
                                     frame_along(o.axis, x));
  return l;
}

}  // namespace

std::vector<Literal> rounded_rectangles(const MeshSurfaces& ms, const Bounds3& domain) {
  const std::vector<Arc> arcs = arcs_of(ms);
  const double tol = 4 * ms.tolerance;
  std::vector<Literal> out;
  for (std::size_t i = 0; i < arcs.size(); ++i)
    for (std::size_t j = i + 1; j < arcs.size(); ++j) {
      Outline o;
      if (!alike(arcs[i], arcs[j], tol) || !outline_of(arcs, i, j, tol, o)) continue;
      out.push_back(outline_literal(o, domain));
    }
  return out;
}

}  // namespace csgfit::construct
