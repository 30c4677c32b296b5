#include "csgfit/model/primitive3d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "model/nurbs_terminal.h"
#include "model/polygonal_solid.h"
#include "model/prism_triangle.h"
#include "model/rounded_box.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Sizes are kept above this so that no formula divides by zero; it is far below any voxel.
constexpr double kMinSize = 1e-9;
// As in 2D: a triangle with its apex further out than this is a sliver no designer would draw.
constexpr double kMaxApex = 4.0;

// |(a, b)|. std::hypot guards against overflow at a cost (a third of a range fit's time went
// to it); coordinates here are bounded far below where the squares would overflow (a mesh is at
// most 1e12 across).
double length2(double a, double b) { return std::sqrt(a * a + b * b); }

// Distance from (px, py) to the segment a-b.
double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double qx = px - ax, qy = py - ay;
  const double len2 = ex * ex + ey * ey;
  const double t = len2 > 0 ? std::clamp((qx * ex + qy * ey) / len2, 0.0, 1.0) : 0.0;
  return length2(qx - t * ex, qy - t * ey);
}

// Exact distance of an extrusion: 2D distance d2 of the section, |z| - half depth dz.
double extrusion_distance(double d2, double dz) {
  return std::min(std::max(d2, dz), 0.0) + length2(std::max(d2, 0.0), std::max(dz, 0.0));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Names

std::string_view to_string(PrimitiveKind3D kind) {
  switch (kind) {
    case PrimitiveKind3D::Box: return "box";
    case PrimitiveKind3D::Sphere: return "sphere";
    case PrimitiveKind3D::Cylinder: return "cylinder";
    case PrimitiveKind3D::Cone: return "cone";
    case PrimitiveKind3D::Ellipsoid: return "ellipsoid";
    case PrimitiveKind3D::Torus: return "torus";
    case PrimitiveKind3D::TriangularPrism: return "prism";
    case PrimitiveKind3D::Nurbs: return "nurbs";
    case PrimitiveKind3D::RoundedBox: return "rounded_box";
  }
  return "?";
}

PrimitiveKind3D primitive_kind3d_from_string(std::string_view name) {
  if (name == "box" || name == "cube" || name == "block") return PrimitiveKind3D::Box;
  if (name == "sphere") return PrimitiveKind3D::Sphere;
  if (name == "cylinder") return PrimitiveKind3D::Cylinder;
  if (name == "cone" || name == "frustum") return PrimitiveKind3D::Cone;
  if (name == "ellipsoid") return PrimitiveKind3D::Ellipsoid;
  if (name == "torus") return PrimitiveKind3D::Torus;
  if (name == "prism" || name == "triangular_prism" || name == "wedge")
    return PrimitiveKind3D::TriangularPrism;
  if (name == "nurbs" || name == "bspline") return PrimitiveKind3D::Nurbs;
  if (name == "rounded_box" || name == "rounded-box" || name == "roundedbox")
    return PrimitiveKind3D::RoundedBox;
  throw std::invalid_argument(
      "unknown 3D primitive '" + std::string(name) +
      "' (expected box, sphere, cylinder, cone, ellipsoid, torus, prism, nurbs or rounded_box)");
}

PrimitiveSet3D PrimitiveSet3D::all() {
  PrimitiveSet3D s;
  for (int i = 0; i <= static_cast<int>(PrimitiveKind3D::TriangularPrism); ++i)
    s.add(static_cast<PrimitiveKind3D>(i));
  return s;
}

PrimitiveSet3D analytic_kinds(PrimitiveSet3D set) {
  set.bits &= ~(1u << static_cast<unsigned>(PrimitiveKind3D::Nurbs));
  return set;
}

PrimitiveSet3D PrimitiveSet3D::matchable() {
  PrimitiveSet3D s = all();
  s.bits &= ~(1u << static_cast<unsigned>(PrimitiveKind3D::Torus));
  return s;
}

PrimitiveSet3D PrimitiveSet3D::parse(const std::string& list) {
  if (list == "all") return all();
  PrimitiveSet3D s;
  std::stringstream ss(list);
  for (std::string name; std::getline(ss, name, ',');) {
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name.empty()) continue;
    s.add(primitive_kind3d_from_string(name));
  }
  if (s.empty()) throw std::invalid_argument("no primitive type given");
  return s;
}

int free_dims(PrimitiveKind3D kind, int out[3]) {
  switch (kind) {
    case PrimitiveKind3D::Sphere: out[0] = 0; return 1;
    case PrimitiveKind3D::Cylinder: out[0] = 0, out[1] = 2; return 2;
    case PrimitiveKind3D::Torus: out[0] = 0, out[1] = 1; return 2;
    default: out[0] = 0, out[1] = 1, out[2] = 2; return 3;
  }
}

bool is_axially_symmetric(PrimitiveKind3D kind) {
  return kind == PrimitiveKind3D::Sphere || kind == PrimitiveKind3D::Cylinder ||
         kind == PrimitiveKind3D::Cone || kind == PrimitiveKind3D::Torus;
}

bool is_axially_symmetric(const Primitive3D& p) {
  return is_axially_symmetric(p.kind) && !p.is_polygonal();
}

// ---------------------------------------------------------------------------------------------
// Primitive3D

namespace {
Primitive3D make(PrimitiveKind3D kind, double cx, double cy, double cz, const Quaternion& q,
                 Vec3 dims, double apex = 0, double corner = 0) {
  Primitive3D p;
  p.kind = kind;
  p.cx = cx, p.cy = cy, p.cz = cz;
  p.rotation = q;
  p.dims = dims;
  p.apex = apex;
  p.corner = corner;
  p.normalize();
  return p;
}
}  // namespace

Primitive3D Primitive3D::box(double cx, double cy, double cz, double sx, double sy, double sz,
                             const Quaternion& rotation) {
  return make(PrimitiveKind3D::Box, cx, cy, cz, rotation, {sx, sy, sz});
}
Primitive3D Primitive3D::sphere(double cx, double cy, double cz, double r) {
  return make(PrimitiveKind3D::Sphere, cx, cy, cz, {}, {r, r, r});
}
Primitive3D Primitive3D::cylinder(double cx, double cy, double cz, double r, double height,
                                  const Quaternion& rotation) {
  return make(PrimitiveKind3D::Cylinder, cx, cy, cz, rotation, {r, r, height});
}
Primitive3D Primitive3D::cone(double cx, double cy, double cz, double r1, double r2,
                              double height, const Quaternion& rotation) {
  return make(PrimitiveKind3D::Cone, cx, cy, cz, rotation, {r1, r2, height});
}
Primitive3D Primitive3D::ellipsoid(double cx, double cy, double cz, double rx, double ry,
                                   double rz, const Quaternion& rotation) {
  return make(PrimitiveKind3D::Ellipsoid, cx, cy, cz, rotation, {rx, ry, rz});
}
Primitive3D Primitive3D::torus(double cx, double cy, double cz, double major_r, double minor_r,
                               const Quaternion& rotation) {
  return make(PrimitiveKind3D::Torus, cx, cy, cz, rotation, {major_r, minor_r, 0});
}
Primitive3D Primitive3D::prism(double cx, double cy, double cz, double w, double h, double depth,
                               double apex, const Quaternion& rotation) {
  return make(PrimitiveKind3D::TriangularPrism, cx, cy, cz, rotation, {w, h, depth}, apex);
}
Primitive3D Primitive3D::rounded_box(double cx, double cy, double cz, double sx, double sy,
                                     double sz, double corner, const Quaternion& rotation) {
  return make(PrimitiveKind3D::RoundedBox, cx, cy, cz, rotation, {sx, sy, sz}, 0, corner);
}
Primitive3D Primitive3D::nurbs(double cx, double cy, double cz, BSplineSurface surface,
                               const Quaternion& rotation) {
  const XYRectangle& r = surface.rectangle();
  const double tol = 1e-9 * std::max(r.x1 - r.x0, r.y1 - r.y0);
  if (!(r.x1 > r.x0 && r.y1 > r.y0) || std::fabs(r.x0 + r.x1) > tol || std::fabs(r.y0 + r.y1) > tol)
    throw std::invalid_argument("a NURBS terminal's patch must be a height field centred on the origin");
  Primitive3D p;
  p.kind = PrimitiveKind3D::Nurbs;
  p.cx = cx, p.cy = cy, p.cz = cz;
  p.rotation = rotation;
  p.patch = std::make_shared<const BSplineSurface>(std::move(surface));
  p.normalize();
  return p;
}

double Primitive3D::volume() const {
  if (is_polygonal()) return polygonal::volume(*this);
  const Vec3& d = dims;
  switch (kind) {
    case PrimitiveKind3D::Box: return d[0] * d[1] * d[2];
    case PrimitiveKind3D::Sphere: return 4.0 / 3.0 * kPi * d[0] * d[0] * d[0];
    case PrimitiveKind3D::Cylinder: return kPi * d[0] * d[0] * d[2];
    case PrimitiveKind3D::Cone:
      return kPi * d[2] / 3.0 * (d[0] * d[0] + d[0] * d[1] + d[1] * d[1]);
    case PrimitiveKind3D::Ellipsoid: return 4.0 / 3.0 * kPi * d[0] * d[1] * d[2];
    case PrimitiveKind3D::Torus: return 2.0 * kPi * kPi * d[0] * d[1] * d[1];
    case PrimitiveKind3D::TriangularPrism: return 0.5 * d[0] * d[1] * d[2];
    case PrimitiveKind3D::Nurbs: return nurbs::volume(*this);
    case PrimitiveKind3D::RoundedBox: return rounded_box::volume(*this);
  }
  return 0;
}

Vec3 Primitive3D::to_local(double x, double y, double z) const {
  const Mat3 m = rotation.matrix();
  const double px = x - cx, py = y - cy, pz = z - cz;
  return {m[0][0] * px + m[1][0] * py + m[2][0] * pz, m[0][1] * px + m[1][1] * py + m[2][1] * pz,
          m[0][2] * px + m[1][2] * py + m[2][2] * pz};
}

bool Primitive3D::contains(double x, double y, double z) const {
  return contains_local(to_local(x, y, z));
}

bool Primitive3D::contains_local(const Vec3& l) const {
  if (is_polygonal()) return polygonal::contains(*this, l);
  const Vec3& d = dims;
  switch (kind) {
    case PrimitiveKind3D::Box:
      return std::fabs(l[0]) <= d[0] / 2 && std::fabs(l[1]) <= d[1] / 2 &&
             std::fabs(l[2]) <= d[2] / 2;
    case PrimitiveKind3D::Sphere: return l[0] * l[0] + l[1] * l[1] + l[2] * l[2] <= d[0] * d[0];
    case PrimitiveKind3D::Ellipsoid: {
      double f = 0;
      for (int i = 0; i < 3; ++i) f += l[i] * l[i] / (d[i] * d[i]);
      return f <= 1;
    }
    case PrimitiveKind3D::Cylinder:
      return std::fabs(l[2]) <= d[2] / 2 && l[0] * l[0] + l[1] * l[1] <= d[0] * d[0];
    case PrimitiveKind3D::Cone: {
      if (std::fabs(l[2]) > d[2] / 2) return false;
      const double radius = d[0] + (d[1] - d[0]) / d[2] * (l[2] + d[2] / 2);
      return radius >= 0 && l[0] * l[0] + l[1] * l[1] <= radius * radius;
    }
    case PrimitiveKind3D::Torus: {
      const double rho = length2(l[0], l[1]) - d[0];
      return rho * rho + l[2] * l[2] <= d[1] * d[1];
    }
    case PrimitiveKind3D::TriangularPrism: {
      if (std::fabs(l[2]) > d[2] / 2) return false;
      double t[3][2];
      triangle_local(*this, t);
      for (int i = 0; i < 3; ++i) {
        const double* a = t[i];
        const double* c = t[(i + 1) % 3];
        if ((c[0] - a[0]) * (l[1] - a[1]) - (c[1] - a[1]) * (l[0] - a[0]) < 0) return false;
      }
      return true;
    }
    case PrimitiveKind3D::Nurbs: return nurbs::contains(*this, l);
    case PrimitiveKind3D::RoundedBox: return rounded_box::contains(*this, l);
  }
  return false;
}

double Primitive3D::signed_distance(double x, double y, double z) const {
  return signed_distance_local(to_local(x, y, z));
}

void Primitive3D::signed_distances(const Vec3* points, std::size_t n, double* out) const {
  // One rotation matrix for all the points: to_local would build it per point.
  const Mat3 m = rotation.matrix();
  for (std::size_t i = 0; i < n; ++i) {
    const double px = points[i][0] - cx, py = points[i][1] - cy, pz = points[i][2] - cz;
    out[i] = signed_distance_local({m[0][0] * px + m[1][0] * py + m[2][0] * pz,
                                    m[0][1] * px + m[1][1] * py + m[2][1] * pz,
                                    m[0][2] * px + m[1][2] * py + m[2][2] * pz});
  }
}

double Primitive3D::signed_distance_local(const Vec3& l) const {
  const Vec3& d = dims;
  if (kind == PrimitiveKind3D::Cylinder && is_polygonal())
    return extrusion_distance(polygonal::section_distance(sides, d[0], l[0], l[1]),
                              std::fabs(l[2]) - d[2] / 2);
  if (is_polygonal()) return polygonal::face_plane_distance(*this, l);
  switch (kind) {
    case PrimitiveKind3D::Box: {
      double q[3], outside = 0, inside = -kInf;
      for (int i = 0; i < 3; ++i) {
        q[i] = std::fabs(l[i]) - d[i] / 2;
        outside += std::max(q[i], 0.0) * std::max(q[i], 0.0);
        inside = std::max(inside, q[i]);
      }
      return std::sqrt(outside) + std::min(inside, 0.0);
    }
    case PrimitiveKind3D::Sphere: return std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) - d[0];
    case PrimitiveKind3D::Ellipsoid: {
      double k0 = 0, k1 = 0;
      for (int i = 0; i < 3; ++i) {
        k0 += (l[i] / d[i]) * (l[i] / d[i]);
        k1 += (l[i] / (d[i] * d[i])) * (l[i] / (d[i] * d[i]));
      }
      k0 = std::sqrt(k0), k1 = std::sqrt(k1);
      if (k1 < 1e-300) return -std::min({d[0], d[1], d[2]});  // the centre
      return k0 * (k0 - 1.0) / k1;
    }
    case PrimitiveKind3D::Cylinder:
      return extrusion_distance(length2(l[0], l[1]) - d[0], std::fabs(l[2]) - d[2] / 2);
    case PrimitiveKind3D::Cone: {
      // A solid of revolution: the distance in the meridian half-plane (rho, z) to the profile
      // (bottom edge, slanted side, top edge; the axis is not a surface) is the 3D distance.
      const double rho = length2(l[0], l[1]), h = d[2] / 2;
      const double dist = std::min({segment_distance(rho, l[2], 0, -h, d[0], -h),
                                    segment_distance(rho, l[2], d[0], -h, d[1], h),
                                    segment_distance(rho, l[2], d[1], h, 0, h)});
      return contains_local(l) ? -dist : dist;
    }
    case PrimitiveKind3D::Torus:
      return length2(length2(l[0], l[1]) - d[0], l[2]) - d[1];
    case PrimitiveKind3D::TriangularPrism: {
      double t[3][2];
      triangle_local(*this, t);
      double best = kInf;
      bool inside = true;
      for (int i = 0; i < 3; ++i) {
        const double* a = t[i];
        const double* c = t[(i + 1) % 3];
        best = std::min(best, segment_distance(l[0], l[1], a[0], a[1], c[0], c[1]));
        if ((c[0] - a[0]) * (l[1] - a[1]) - (c[1] - a[1]) * (l[0] - a[0]) < 0) inside = false;
      }
      return extrusion_distance(inside ? -best : best, std::fabs(l[2]) - d[2] / 2);
    }
    case PrimitiveKind3D::Nurbs: return nurbs::signed_distance(*this, l);
    case PrimitiveKind3D::RoundedBox:
      return extrusion_distance(rounded_box::section_distance(*this, l[0], l[1]),
                                std::fabs(l[2]) - d[2] / 2);
  }
  return 0;
}

Vec3 Primitive3D::normal_at(double x, double y, double z) const {
  const double scale = std::max({dims[0], dims[1], dims[2], 1e-6});
  const double h = 1e-6 * scale;
  Vec3 g{signed_distance(x + h, y, z) - signed_distance(x - h, y, z),
         signed_distance(x, y + h, z) - signed_distance(x, y - h, z),
         signed_distance(x, y, z + h) - signed_distance(x, y, z - h)};
  const double n = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(n > 0)) return {0, 0, 0};
  return {g[0] / n, g[1] / n, g[2] / n};
}

Bounds3 Primitive3D::bounds() const {
  if (is_polygonal()) return polygonal::bounds(*this);
  const Mat3 m = rotation.matrix();
  const Vec3& d = dims;
  const Vec3 c{cx, cy, cz};
  Bounds3 out;
  auto symmetric = [&](const Vec3& e) {
    for (int i = 0; i < 3; ++i) out.lo[i] = c[i] - e[i], out.hi[i] = c[i] + e[i];
  };
  // Half extent along model axis i of a disc of radius r whose normal is the local z axis.
  auto disc = [&](int i, double r) { return r * std::sqrt(std::max(0.0, 1 - m[i][2] * m[i][2])); };
  switch (kind) {
    case PrimitiveKind3D::Box: {
      Vec3 e{};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) e[i] += std::fabs(m[i][j]) * d[j] / 2;
      symmetric(e);
      break;
    }
    case PrimitiveKind3D::Sphere: symmetric({d[0], d[0], d[0]}); break;
    case PrimitiveKind3D::Ellipsoid: {
      Vec3 e{};
      for (int i = 0; i < 3; ++i)
        e[i] = std::sqrt(m[i][0] * m[i][0] * d[0] * d[0] + m[i][1] * m[i][1] * d[1] * d[1] +
                         m[i][2] * m[i][2] * d[2] * d[2]);
      symmetric(e);
      break;
    }
    case PrimitiveKind3D::Cylinder:
    case PrimitiveKind3D::Cone: {
      const double r_bottom = d[0];
      const double r_top = kind == PrimitiveKind3D::Cone ? d[1] : d[0];
      for (int i = 0; i < 3; ++i) {
        const double bottom = c[i] - m[i][2] * d[2] / 2, top = c[i] + m[i][2] * d[2] / 2;
        out.lo[i] = std::min(bottom - disc(i, r_bottom), top - disc(i, r_top));
        out.hi[i] = std::max(bottom + disc(i, r_bottom), top + disc(i, r_top));
      }
      break;
    }
    case PrimitiveKind3D::Torus: {
      Vec3 e{};
      for (int i = 0; i < 3; ++i) e[i] = disc(i, d[0]) + d[1];
      symmetric(e);
      break;
    }
    case PrimitiveKind3D::Nurbs: {
      // The convex hull property: the patch lies between its lowest and highest control heights.
      double low = 0;
      for (const Vec3& v : patch->net()) low = std::min(low, v[2]);
      out.lo = {kInf, kInf, kInf};
      out.hi = {-kInf, -kInf, -kInf};
      for (double lx : {-d[0] / 2, d[0] / 2})
        for (double ly : {-d[1] / 2, d[1] / 2})
          for (double lz : {low, d[2]})
            for (int i = 0; i < 3; ++i) {
              const double w = c[i] + m[i][0] * lx + m[i][1] * ly + m[i][2] * lz;
              out.lo[i] = std::min(out.lo[i], w);
              out.hi[i] = std::max(out.hi[i], w);
            }
      break;
    }
    case PrimitiveKind3D::RoundedBox: return rounded_box::bounds(*this);
    case PrimitiveKind3D::TriangularPrism: {
      double t[3][2];
      triangle_local(*this, t);
      out.lo = {kInf, kInf, kInf};
      out.hi = {-kInf, -kInf, -kInf};
      for (int v = 0; v < 3; ++v)
        for (double lz : {-d[2] / 2, d[2] / 2})
          for (int i = 0; i < 3; ++i) {
            const double w = c[i] + m[i][0] * t[v][0] + m[i][1] * t[v][1] + m[i][2] * lz;
            out.lo[i] = std::min(out.lo[i], w);
            out.hi[i] = std::max(out.hi[i], w);
          }
      break;
    }
  }
  return out;
}

void Primitive3D::normalize() {
  rotation.normalize();
  for (double& v : dims) v = std::fabs(v);
  switch (kind) {
    case PrimitiveKind3D::Sphere:
      dims[0] = std::max(dims[0], kMinSize);
      dims[1] = dims[2] = dims[0];
      rotation = Quaternion{};
      break;
    case PrimitiveKind3D::Cylinder:
      dims[0] = std::max(dims[0], kMinSize);
      dims[1] = dims[0];
      dims[2] = std::max(dims[2], kMinSize);
      break;
    case PrimitiveKind3D::Cone:
      // One radius may be 0 (a full cone), not both.
      if (std::max(dims[0], dims[1]) < kMinSize) dims[0] = kMinSize;
      dims[2] = std::max(dims[2], kMinSize);
      break;
    case PrimitiveKind3D::Torus:
      dims[0] = std::max(dims[0], kMinSize);
      dims[1] = std::clamp(dims[1], kMinSize, dims[0]);
      dims[2] = 0;
      break;
    case PrimitiveKind3D::Nurbs:
      // The patch is the shape; dims only report it (a search moves the net, not dims).
      if (patch) dims = nurbs::dims_of(*patch);
      break;
    default:
      for (double& v : dims) v = std::max(v, kMinSize);
      break;
  }
  if (kind == PrimitiveKind3D::TriangularPrism)
    apex = std::isfinite(apex) ? std::clamp(apex, -kMaxApex, kMaxApex) : 0.0;
  else
    apex = 0;
  if (kind != PrimitiveKind3D::Nurbs) patch.reset();
  if (kind == PrimitiveKind3D::Cylinder || kind == PrimitiveKind3D::Cone)
    sides = sides <= 0 ? 0 : std::clamp(sides, 3, kMaxSides);
  else
    sides = 0;
  // A corner of 0 would be a Box's; NaN (a step gone wrong) falls back the same way.
  if (kind == PrimitiveKind3D::RoundedBox)
    corner = std::min(corner > kMinSize ? corner : kMinSize, std::min(dims[0], dims[1]) / 2);
  else
    corner = 0;
}

bool Primitive3D::operator==(const Primitive3D& o) const {
  return kind == o.kind && cx == o.cx && cy == o.cy && cz == o.cz && rotation == o.rotation &&
         dims == o.dims && apex == o.apex && sides == o.sides && corner == o.corner &&
         nurbs::same_patch(patch.get(), o.patch.get());
}

Bounds3 merged(const Bounds3& a, const Bounds3& b) {
  Bounds3 m;
  for (int i = 0; i < 3; ++i) m.lo[i] = std::min(a.lo[i], b.lo[i]), m.hi[i] = std::max(a.hi[i], b.hi[i]);
  return m;
}

Bounds3 bounds_of(const std::vector<Vec3>& points) {
  Bounds3 b{points.front(), points.front()};
  for (const Vec3& p : points) b = merged(b, Bounds3{p, p});
  return b;
}

bool clip_ray(const Bounds3& box, const Vec3& o, const Vec3& d, double& t0, double& t1) {
  t0 = 0, t1 = std::numeric_limits<double>::max();
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-300) {
      if (o[i] < box.lo[i] || o[i] > box.hi[i]) return false;
      continue;
    }
    double a = (box.lo[i] - o[i]) / d[i], b = (box.hi[i] - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
  }
  return t0 <= t1;
}

}  // namespace csgfit
