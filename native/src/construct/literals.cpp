#include "literals.h"

#include <algorithm>
#include <cmath>

#include "model/linalg.h"
#include "rounded_rectangles.h"
#include "tuning.h"

namespace csgfit::construct {

namespace {

using namespace linalg;

Vec3 axis_unit(int a) {
  Vec3 v{0, 0, 0};
  v[a] = 1;
  return v;
}

// Two directions across `d`: the model axes when d is one, else any pair.
void across(const Vec3& d, Vec3& u, Vec3& w) {
  const int a = model_axis(d);
  if (a >= 0) {
    u = axis_unit((a + 1) % 3), w = axis_unit((a + 2) % 3);
    return;
  }
  u = normalized(reject(std::abs(d[0]) < 0.9 ? axis_unit(0) : axis_unit(1), d));
  w = cross(d, u);
}

struct Domain {
  Vec3 centre{0, 0, 0};
  double diagonal = 0;
};

Literal plane(Vec3 n, double offset, bool separating) {
  Literal l;
  // A face along a model axis to the file's rounding is along it: one box, not a turned slab.
  for (int a = 0; a < 3; ++a)
    if (std::abs(std::abs(n[a]) - 1) < 1e-10) n = scale(axis_unit(a), n[a] > 0 ? 1 : -1);
  l.normal = n;
  l.offset = offset;
  l.separating = separating;
  return l;
}

Literal solid(const Primitive3D& p, bool separating) {
  Literal l;
  l.plane = false;
  l.solid = p;
  l.separating = separating;
  return l;
}

// A cylinder about the axis through `c`, as long as the domain is wide.
Primitive3D long_cylinder(const Vec3& c, const Vec3& d, double r, const Domain& dom, const Vec3& phase) {
  const Vec3 mid = add(c, scale(d, dot(sub(dom.centre, c), d)));
  return Primitive3D::cylinder(mid[0], mid[1], mid[2], r, 2 * dom.diagonal, frame_along(d, phase));
}

void add_cylinder(const MeshSurface& s, const Domain& dom, int max_sides, std::vector<Literal>& out) {
  const SurfacePatch& p = s.shape;
  const bool polygon = s.sides > 0 && s.sides <= max_sides;
  Primitive3D c = long_cylinder(p.point, p.axis, polygon ? p.radius : area_radius(p.radius, s.sides),
                                dom, s.vertex_direction);
  if (polygon) c.sides = s.sides;
  out.push_back(solid(c, false));
  // A whole hole or boss needs no plane through its axis; a rounded corner or a slot's end
  // does, to part the arc's cells from the block beside it.
  if (s.sweep >= kWholeSweep) return;
  Vec3 u, w;
  across(p.axis, u, w);
  out.push_back(plane(u, dot(u, p.point), true));
  out.push_back(plane(w, dot(w, p.point), true));
}

void add_cone(const MeshSurface& s, const Domain& dom, std::vector<Literal>& out) {
  const SurfacePatch& p = s.shape;
  const double h = dot(sub(dom.centre, p.point), p.axis) + dom.diagonal;
  if (!(h > 0) || !(p.angle > 0) || p.angle >= M_PI / 2) return;
  const Vec3 mid = add(p.point, scale(p.axis, h / 2));
  out.push_back(solid(Primitive3D::cone(mid[0], mid[1], mid[2], 0, h * std::tan(p.angle), h,
                                        frame_along(p.axis, axis_unit(0))), false));
  out.push_back(plane(p.axis, dot(p.axis, p.point), true));
}

void add_round(const MeshSurface& s, const Domain& dom, std::vector<Literal>& out) {
  const SurfacePatch& p = s.shape;
  const Vec3& c = p.point;
  if (p.kind == SurfaceKind::Sphere) {
    out.push_back(solid(Primitive3D::sphere(c[0], c[1], c[2], p.radius), false));
    for (int a = 0; a < 3; ++a) out.push_back(plane(axis_unit(a), c[a], true));
    return;
  }
  if (!(p.minor_radius <= p.radius)) return;
  out.push_back(solid(Primitive3D::torus(c[0], c[1], c[2], p.radius, p.minor_radius, frame_along(p.axis, axis_unit(0))), false));
  // The core circle's plane and cylinder part the tube's inner and outer, upper and lower halves.
  out.push_back(plane(p.axis, dot(p.axis, c), true));
  out.push_back(solid(long_cylinder(c, p.axis, p.radius, dom, axis_unit(0)), true));
}

PrimitiveKind3D kind_of(SurfaceKind k) {
  switch (k) {
    case SurfaceKind::Plane: return PrimitiveKind3D::Box;
    case SurfaceKind::Sphere: return PrimitiveKind3D::Sphere;
    case SurfaceKind::Cylinder: return PrimitiveKind3D::Cylinder;
    case SurfaceKind::Cone: return PrimitiveKind3D::Cone;
    case SurfaceKind::Torus: return PrimitiveKind3D::Torus;
  }
  return PrimitiveKind3D::Box;
}

// Planes with either side out are one literal (the construction uses both sides).
bool same(const Literal& a, const Literal& b, double tol) {
  if (a.plane != b.plane) return false;
  if (a.plane) {
    const double d = dot(a.normal, b.normal);
    return std::abs(std::abs(d) - 1) < 1e-9 && std::abs(a.offset - (d > 0 ? b.offset : -b.offset)) <= tol;
  }
  const Primitive3D &p = a.solid, &q = b.solid;
  if (p.kind != q.kind || p.sides != q.sides || std::abs(p.corner - q.corner) > tol ||
      norm(sub({p.cx, p.cy, p.cz}, {q.cx, q.cy, q.cz})) > tol)
    return false;
  for (int k = 0; k < 3; ++k)
    if (std::abs(p.dims[k] - q.dims[k]) > tol) return false;
  const Mat3 m = p.rotation.matrix(), n = q.rotation.matrix();
  return norm(cross(column(m, 2), column(n, 2))) < 1e-6 && norm(cross(column(m, 0), column(n, 0))) < 1e-6;
}

}  // namespace

bool Literal::contains(const Vec3& p) const {
  if (plane) return dot(normal, p) <= offset;
  return solid.contains(p[0], p[1], p[2]);
}

Quaternion frame_along(const Vec3& z, const Vec3& x) {
  Vec3 u = normalized(reject(x, z));
  if (norm(u) < 0.5) u = normalized(reject(std::abs(z[0]) < 0.9 ? axis_unit(0) : axis_unit(1), z));
  const Vec3 v = cross(z, u);
  Mat3 m;
  for (int r = 0; r < 3; ++r) m[r] = {u[r], v[r], z[r]};
  return quaternion_from_matrix(m);
}

double area_radius(double circumradius, int sides) {
  if (sides <= 0) return circumradius;
  return circumradius * std::sqrt(sides * std::sin(2 * M_PI / sides) / (2 * M_PI));
}

int model_axis(const Vec3& d) {
  for (int a = 0; a < 3; ++a)
    if (std::abs(std::abs(d[a]) - 1) < 1e-12) return a;
  return -1;
}

std::vector<Literal> literals_of(const MeshSurfaces& surfaces, const Bounds3& domain,
                                 int max_polygon_sides, const PrimitiveSet3D& kinds) {
  Domain dom;
  dom.centre = scale(add(domain.lo, domain.hi), 0.5);
  dom.diagonal = norm(sub(domain.hi, domain.lo));
  std::vector<Literal> all;
  for (const MeshSurface& s : surfaces.surfaces) {
    if (!kinds.has(kind_of(s.shape.kind))) continue;
    switch (s.shape.kind) {
      case SurfaceKind::Plane: all.push_back(plane(s.shape.axis, dot(s.shape.axis, s.shape.point), false)); break;
      case SurfaceKind::Cylinder: add_cylinder(s, dom, max_polygon_sides, all); break;
      case SurfaceKind::Cone: add_cone(s, dom, all); break;
      case SurfaceKind::Sphere:
      case SurfaceKind::Torus: add_round(s, dom, all); break;
    }
  }
  if (kinds.has(PrimitiveKind3D::RoundedBox))
    for (Literal& l : rounded_rectangles(surfaces, domain)) all.push_back(std::move(l));
  // A face's literal wins over a separating twin (it says the face is there).
  std::stable_sort(all.begin(), all.end(), [](const Literal& a, const Literal& b) { return !a.separating && b.separating; });
  std::vector<Literal> out;
  for (const Literal& l : all)
    if (std::none_of(out.begin(), out.end(), [&](const Literal& k) { return same(k, l, 2 * surfaces.tolerance); }))
      out.push_back(l);
  return out;
}

}  // namespace csgfit::construct
