// The polygonal Cylinder and Cone: OpenSCAD's cylinder(h, r1, r2, $fn = n), a frustum of a
// regular pyramid whose circumradius goes linearly from dims[0] at z = -h/2 to the top radius
// at z = +h/2. Vertex i of each end lies at 360 i / n degrees, so edge k (vertex k to k + 1)
// faces (k + 1/2) 360 / n degrees.
#include "model/polygonal_solid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace csgfit::polygonal {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

double top_radius(const Primitive3D& p) {
  return p.kind == PrimitiveKind3D::Cone ? p.dims[1] : p.dims[0];
}
// How much the circumradius grows per unit of local z.
double radius_slope(const Primitive3D& p) { return (top_radius(p) - p.dims[0]) / p.dims[2]; }
double radius_at(const Primitive3D& p, double z) {
  return p.dims[0] + radius_slope(p) * (z + p.dims[2] / 2);
}
// The distance of each edge from the centre per unit of circumradius.
double apothem_ratio(int n) { return std::cos(kPi / n); }
double normal_angle(int n, double k) { return 2 * kPi * (k + 0.5) / n; }

// A point in the frame of the edge whose angular sector (between the rays through its two
// vertices) holds it: `along_normal` along the edge's outward normal, `along_edge` across it.
// The polygon is symmetric about every ray through a vertex, so a point's nearest boundary
// point lies on its own sector's edge, and along_normal is the largest of its coordinates
// along the edge normals.
struct EdgeFrame {
  double along_normal, along_edge;
};

EdgeFrame edge_frame(int n, double x, double y) {
  const double a = normal_angle(n, std::floor(std::atan2(y, x) * n / (2 * kPi)));
  const double c = std::cos(a), s = std::sin(a);
  return {c * x + s * y, c * y - s * x};
}

}  // namespace

double section_distance(int n, double r, double x, double y) {
  const EdgeFrame q = edge_frame(n, x, y);
  const double out = q.along_normal - r * apothem_ratio(n);
  // Inside, the foot on the edge's line lies on the edge: the sector narrows to the centre.
  if (out <= 0) return out;
  const double half_edge = r * std::sin(kPi / n);
  const double off = q.along_edge - std::clamp(q.along_edge, -half_edge, half_edge);
  return std::sqrt(out * out + off * off);
}

bool contains(const Primitive3D& p, const Vec3& l) {
  if (std::fabs(l[2]) > p.dims[2] / 2) return false;
  return edge_frame(p.sides, l[0], l[1]).along_normal <=
         apothem_ratio(p.sides) * radius_at(p, l[2]);
}

double face_plane_distance(const Primitive3D& p, const Vec3& l) {
  const double c = apothem_ratio(p.sides), k = radius_slope(p);
  // Side face: along_normal - c radius(z) = 0, whose gradient in (along_normal, z) is (1, -c k).
  const double side = (edge_frame(p.sides, l[0], l[1]).along_normal - c * radius_at(p, l[2])) /
                      std::sqrt(1 + c * c * k * k);
  return std::max(side, std::fabs(l[2]) - p.dims[2] / 2);
}

double volume(const Primitive3D& p) {
  const double r1 = p.dims[0], r2 = top_radius(p);
  // The section's area is (n/2) sin(360/n) r(z)^2; its integral over z is the prismatoid's.
  return 0.5 * p.sides * std::sin(2 * kPi / p.sides) * p.dims[2] / 3 *
         (r1 * r1 + r1 * r2 + r2 * r2);
}

Bounds3 bounds(const Primitive3D& p) {
  const Mat3 m = p.rotation.matrix();
  const Vec3 c{p.cx, p.cy, p.cz};
  const double h = p.dims[2];
  Bounds3 out{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (int i = 0; i < p.sides; ++i) {
    const double a = 2 * kPi * i / p.sides;
    for (const auto& [z, r] : {std::pair{-h / 2, p.dims[0]}, std::pair{h / 2, top_radius(p)}}) {
      const Vec3 l{r * std::cos(a), r * std::sin(a), z};
      for (int j = 0; j < 3; ++j) {
        const double w = c[j] + m[j][0] * l[0] + m[j][1] * l[1] + m[j][2] * l[2];
        out.lo[j] = std::min(out.lo[j], w);
        out.hi[j] = std::max(out.hi[j], w);
      }
    }
  }
  return out;
}

void clip_line(const Primitive3D& p, const Vec3& u, const Vec3& b, interval::Interval& iv) {
  const double h = p.dims[2], c = apothem_ratio(p.sides), k = radius_slope(p);
  interval::clip_linear(iv, u[2], b[2], -h / 2, h / 2);
  // The edge normals by turning the first one edge by edge: two sines a line instead of two a
  // side (a rasterised row is one line; the rounding stays far below 1e-12 at 1000 sides).
  const double step = 2 * kPi / p.sides, cs = std::cos(step), sn = std::sin(step);
  double nx = std::cos(normal_angle(p.sides, 0)), ny = std::sin(normal_angle(p.sides, 0));
  for (int e = 0; e < p.sides && !iv.empty(); ++e) {
    // Inside face e: c radius(z) - (nx x + ny y) >= 0, linear in s along the line.
    interval::clip_halfline(iv, c * k * u[2] - (nx * u[0] + ny * u[1]),
                            c * (p.dims[0] + k * (b[2] + h / 2)) - (nx * b[0] + ny * b[1]));
    const double next_x = nx * cs - ny * sn;
    ny = ny * cs + nx * sn;
    nx = next_x;
  }
}

}  // namespace csgfit::polygonal
