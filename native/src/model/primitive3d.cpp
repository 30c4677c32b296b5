#include "csgfit/model/primitive3d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Sizes are kept above this so that no formula divides by zero; it is far below any voxel.
constexpr double kMinSize = 1e-9;
// As in 2D: a triangle with its apex further out than this is a sliver no designer would draw.
constexpr double kMaxApex = 4.0;

struct Interval {
  double lo = -kInf;
  double hi = kInf;
  bool empty() const { return !(lo <= hi); }
};

// Up to four disjoint, sorted intervals of the line parameter (a line meets a torus at most
// four times, so two intervals suffice; four leaves room for rounding).
struct Spans {
  Interval iv[4];
  int n = 0;
  void add(double lo, double hi) {
    if (!(lo <= hi) || n == 4) return;
    if (n > 0 && lo <= iv[n - 1].hi) {
      iv[n - 1].hi = std::max(iv[n - 1].hi, hi);
      return;
    }
    iv[n++] = Interval{lo, hi};
  }
};

// Narrows `iv` to the s where lo <= a*s + b <= hi.
inline void clip_linear(Interval& iv, double a, double b, double lo, double hi) {
  if (std::fabs(a) < 1e-12) {
    if (b < lo || b > hi) iv.lo = 1, iv.hi = 0;
    return;
  }
  double s0 = (lo - b) / a;
  double s1 = (hi - b) / a;
  if (s0 > s1) std::swap(s0, s1);
  iv.lo = std::max(iv.lo, s0);
  iv.hi = std::min(iv.hi, s1);
}

// Narrows `iv` to the s where a*s + b >= 0.
inline void clip_halfline(Interval& iv, double a, double b) {
  if (std::fabs(a) < 1e-12) {
    if (b < 0) iv.lo = 1, iv.hi = 0;
    return;
  }
  const double s = -b / a;
  if (a > 0)
    iv.lo = std::max(iv.lo, s);
  else
    iv.hi = std::min(iv.hi, s);
}

// The s where A s^2 + 2 beta s + C <= 0 and s in `clip`, appended to `out` (A may have any
// sign: a double cone's quadric opens both ways).
void quadric_spans(double A, double beta, double C, const Interval& clip, Spans& out) {
  if (clip.empty()) return;
  const double scale = std::max({std::fabs(A), std::fabs(beta), 1e-300});
  if (std::fabs(A) < 1e-13 * scale || A == 0) {
    Interval iv = clip;
    clip_halfline(iv, -2 * beta, -C);
    out.add(iv.lo, iv.hi);
    return;
  }
  const double disc = beta * beta - A * C;
  if (disc < 0) {
    if (A < 0) out.add(clip.lo, clip.hi);  // negative everywhere
    return;
  }
  // Cancellation-free roots: q = -(beta + sign(beta) sqrt(disc)); roots q/A and C/q.
  const double root = std::sqrt(disc);
  const double q = -(beta + std::copysign(root, beta));
  double r0, r1;
  if (q == 0) {
    r0 = r1 = 0;
  } else {
    r0 = q / A;
    r1 = C / q;
  }
  if (r0 > r1) std::swap(r0, r1);
  if (A > 0) {
    out.add(std::max(clip.lo, r0), std::min(clip.hi, r1));
  } else {
    out.add(clip.lo, std::min(clip.hi, r0));
    out.add(std::max(clip.lo, r1), clip.hi);
  }
}

// Root of a polynomial (coefficients c[0] + c[1] s + ... , degree deg) in [a, b] where its
// values fa, fb have opposite signs: Newton steps kept inside a shrinking bracket.
double bracketed_root(const double* c, int deg, double a, double b, double fa) {
  auto eval = [&](double s, double& df) {
    double f = c[deg];
    df = 0;
    for (int i = deg - 1; i >= 0; --i) {
      df = df * s + f;
      f = f * s + c[i];
    }
    return f;
  };
  double s = 0.5 * (a + b);
  for (int it = 0; it < 100; ++it) {
    double df;
    const double f = eval(s, df);
    if (f == 0) return s;
    if ((f < 0) == (fa < 0))
      a = s, fa = f;
    else
      b = s;
    double next = s - f / df;
    if (!(df != 0) || !(next > a && next < b)) next = 0.5 * (a + b);
    if (std::fabs(next - s) <= 1e-15 * (1 + std::fabs(s)) || b - a <= 1e-14 * (1 + std::fabs(s)))
      return next;
    s = next;
  }
  return s;
}

double poly_eval(const double* c, int deg, double s) {
  double f = c[deg];
  for (int i = deg - 1; i >= 0; --i) f = f * s + c[i];
  return f;
}

// Real roots of the polynomial in (a, b), sorted, found through the roots of its derivative
// (which split [a, b] into monotone pieces), recursively down to a quadratic. Returns count.
int roots_in(const double* c, int deg, double a, double b, double* out) {
  if (deg == 1) {
    if (c[1] == 0) return 0;
    const double s = -c[0] / c[1];
    if (s > a && s < b) {
      out[0] = s;
      return 1;
    }
    return 0;
  }
  double d[4];
  for (int i = 1; i <= deg; ++i) d[i - 1] = i * c[i];
  double crit[4];
  const int nc = roots_in(d, deg - 1, a, b, crit);
  double pts[6];
  int np = 0;
  pts[np++] = a;
  for (int i = 0; i < nc; ++i) pts[np++] = crit[i];
  pts[np++] = b;
  int n = 0;
  double fprev = poly_eval(c, deg, pts[0]);
  for (int i = 1; i < np; ++i) {
    const double f = poly_eval(c, deg, pts[i]);
    if ((fprev < 0) != (f < 0) && fprev != 0 && f != 0)
      out[n++] = bracketed_root(c, deg, pts[i - 1], pts[i], fprev);
    else if (f == 0 && i < np - 1)
      out[n++] = pts[i];
    fprev = f;
  }
  return n;
}

// Largest real root of m^3 + a m^2 + b m + c (closed form, then one Newton step).
double largest_cubic_root(double a, double b, double c) {
  const double p = b - a * a / 3;
  const double q = 2 * a * a * a / 27 - a * b / 3 + c;
  const double disc = q * q / 4 + p * p * p / 27;
  double y;
  if (disc > 0) {
    // One real root: Cardano with the cancellation-free sign and u v = -p / 3 (one cbrt).
    const double u = -std::copysign(std::cbrt(std::fabs(q) / 2 + std::sqrt(disc)), q);
    y = u != 0 ? u - p / (3 * u) : 0.0;
  } else {
    const double rp = std::sqrt(std::max(-p / 3, 0.0));
    const double arg = rp > 0 ? std::clamp(-q / (2 * rp * rp * rp), -1.0, 1.0) : 0.0;
    y = 2 * rp * std::cos(std::acos(arg) / 3);
  }
  double m = y - a / 3;
  const double f = ((m + a) * m + b) * m + c;
  const double df = (3 * m + 2 * a) * m + b;
  if (df != 0 && std::isfinite(f / df)) m -= f / df;
  return m;
}

// Appends the real roots of t^2 + b t + c to out.
void quadratic_roots(double b, double c, double* out, int& n) {
  const double disc = b * b - 4 * c;
  if (disc < 0) return;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  if (q == 0) {
    out[n++] = 0;
    return;
  }
  out[n++] = q;
  out[n++] = c / q;
}

// Real roots in (lo, hi) of the quartic c[0] + c[1] s + ... + c[4] s^4, sorted. Ferrari's
// closed form (a resolvent cubic and two quadratics), each root polished by Newton steps on
// the quartic itself; the derivative-splitting search is the fallback when that goes wrong.
// A root pair lost to rounding near a tangent line bounds an interval far thinner than a
// voxel.
int torus_roots(const double* c, double lo, double hi, double* out) {
  const double inv = 1.0 / c[4];
  const double a = c[3] * inv, b = c[2] * inv, cc = c[1] * inv, d = c[0] * inv;
  const double a2 = a * a;
  const double p = b - 3 * a2 / 8;
  const double q = cc - a * b / 2 + a2 * a / 8;
  const double r = d - a * cc / 4 + a2 * b / 16 - 3 * a2 * a2 / 256;
  double t[4];
  int nt = 0;
  const double m = std::fabs(q) > 1e-14 ? largest_cubic_root(p, p * p / 4 - r, -q * q / 8) : 0;
  if (m > 1e-14) {
    const double s2 = std::sqrt(2 * m);
    quadratic_roots(-s2, p / 2 + m + q / (2 * s2), t, nt);
    quadratic_roots(s2, p / 2 + m - q / (2 * s2), t, nt);
  } else {
    // Biquadratic: z = t^2 solves z^2 + p z + r = 0.
    double z[2];
    int nz = 0;
    quadratic_roots(p, r, z, nz);
    for (int i = 0; i < nz; ++i)
      if (z[i] >= 0) t[nt++] = std::sqrt(z[i]), t[nt++] = -std::sqrt(z[i]);
  }
  int n = 0;
  bool ok = true;
  for (int i = 0; i < nt; ++i) {
    double s = t[i] - a / 4;
    // One Newton step: the closed form is good to ~1e-8 here, one step squares that.
    for (int it = 0; it < 1; ++it) {
      const double f = (((c[4] * s + c[3]) * s + c[2]) * s + c[1]) * s + c[0];
      const double df = ((4 * c[4] * s + 3 * c[3]) * s + 2 * c[2]) * s + c[1];
      if (df == 0) break;
      s -= f / df;
    }
    if (!std::isfinite(s)) ok = false;
    if (s > lo && s < hi) out[n++] = s;
  }
  if (!ok) return roots_in(c, 4, lo, hi, out);
  for (int i = 1; i < n; ++i)  // insertion sort of at most four roots
    for (int j = i; j > 0 && out[j] < out[j - 1]; --j) std::swap(out[j], out[j - 1]);
  return n;
}

// Triangle vertices of a prism (or the 2D Triangle) in its local xy, counter-clockwise.
void triangle_local(const Primitive3D& p, double t[3][2]) {
  const double w = p.dims[0], h = p.dims[1];
  t[0][0] = -w / 2, t[0][1] = -h / 2;
  t[1][0] = w / 2, t[1][1] = -h / 2;
  t[2][0] = p.apex * w / 2, t[2][1] = h / 2;
}

// The line x -> (x, y, z) in p's local frame is local(s) = u * s + b with s = x - cx.
// Appends the s-intervals inside p.
void line_spans(const Primitive3D& p, const Vec3& u, const Vec3& b, Spans& out) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box: {
      Interval iv;
      for (int i = 0; i < 3; ++i) clip_linear(iv, u[i], b[i], -d[i] / 2, d[i] / 2);
      out.add(iv.lo, iv.hi);
      return;
    }
    case PrimitiveKind3D::Sphere: {
      const double A = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
      const double beta = u[0] * b[0] + u[1] * b[1] + u[2] * b[2];
      const double C = b[0] * b[0] + b[1] * b[1] + b[2] * b[2] - d[0] * d[0];
      quadric_spans(A, beta, C, Interval{}, out);
      return;
    }
    case PrimitiveKind3D::Ellipsoid: {
      double A = 0, beta = 0, C = -1;
      for (int i = 0; i < 3; ++i) {
        const double inv = 1.0 / (d[i] * d[i]);
        A += u[i] * u[i] * inv;
        beta += u[i] * b[i] * inv;
        C += b[i] * b[i] * inv;
      }
      quadric_spans(A, beta, C, Interval{}, out);
      return;
    }
    case PrimitiveKind3D::Cylinder: {
      Interval iv;
      clip_linear(iv, u[2], b[2], -d[2] / 2, d[2] / 2);
      const double A = u[0] * u[0] + u[1] * u[1];
      const double beta = u[0] * b[0] + u[1] * b[1];
      const double C = b[0] * b[0] + b[1] * b[1] - d[0] * d[0];
      quadric_spans(A, beta, C, iv, out);
      return;
    }
    case PrimitiveKind3D::Cone: {
      // radius(z) = r1 + k (z + h/2) = m s + n along the line; inside: rho^2 <= radius^2 with
      // radius >= 0 (the other nappe of the double cone is outside) and |z| <= h/2.
      const double h = d[2];
      const double k = (d[1] - d[0]) / h;
      const double m = k * u[2];
      const double n = d[0] + k * (b[2] + h / 2);
      Interval iv;
      clip_linear(iv, u[2], b[2], -h / 2, h / 2);
      clip_halfline(iv, m, n);
      const double A = u[0] * u[0] + u[1] * u[1] - m * m;
      const double beta = u[0] * b[0] + u[1] * b[1] - m * n;
      const double C = b[0] * b[0] + b[1] * b[1] - n * n;
      quadric_spans(A, beta, C, iv, out);
      return;
    }
    case PrimitiveKind3D::TriangularPrism: {
      Interval iv;
      clip_linear(iv, u[2], b[2], -d[2] / 2, d[2] / 2);
      double t[3][2];
      triangle_local(p, t);
      for (int i = 0; i < 3; ++i) {
        const double* a = t[i];
        const double* c = t[(i + 1) % 3];
        const double ex = c[0] - a[0], ey = c[1] - a[1];
        // cross(c - a, q - a) >= 0 with q = (u0 s + b0, u1 s + b1): linear in s.
        clip_halfline(iv, ex * u[1] - ey * u[0], ex * (b[1] - a[1]) - ey * (b[0] - a[0]));
      }
      out.add(iv.lo, iv.hi);
      return;
    }
    case PrimitiveKind3D::Torus: {
      // In units of R: f(s) = (|q|^2 + 1 - r^2)^2 - 4 (qx^2 + qy^2) <= 0 with q = local / R,
      // a quartic in s; bracket it by the bounding sphere and the slab |qz| <= r first.
      const double R = d[0];
      const double r = d[1] / R;
      const Vec3 bb{b[0] / R, b[1] / R, b[2] / R};
      // s is measured in units of R from here on (u is unit length, so q(s') = u s' + bb).
      Interval iv;
      clip_linear(iv, u[2], bb[2], -r, r);
      const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
      const double ub = u[0] * bb[0] + u[1] * bb[1] + u[2] * bb[2];
      const double qb = bb[0] * bb[0] + bb[1] * bb[1] + bb[2] * bb[2];
      {
        Spans sphere;
        quadric_spans(uu, ub, qb - (1 + r) * (1 + r), iv, sphere);
        if (sphere.n == 0) return;
        iv = sphere.iv[0];
      }
      const double alpha = uu, beta1 = 2 * ub, gamma = qb + 1 - r * r;
      const double delta = u[0] * u[0] + u[1] * u[1];
      const double eps = 2 * (u[0] * bb[0] + u[1] * bb[1]);
      const double zeta = bb[0] * bb[0] + bb[1] * bb[1];
      const double c[5] = {gamma * gamma - 4 * zeta, 2 * beta1 * gamma - 4 * eps,
                           beta1 * beta1 + 2 * alpha * gamma - 4 * delta, 2 * alpha * beta1,
                           alpha * alpha};
      double roots[4];
      const int nr = torus_roots(c, iv.lo, iv.hi, roots);
      double pts[6];
      int np = 0;
      pts[np++] = iv.lo;
      for (int i = 0; i < nr; ++i) pts[np++] = roots[i];
      pts[np++] = iv.hi;
      for (int i = 1; i < np; ++i) {
        if (poly_eval(c, 4, 0.5 * (pts[i - 1] + pts[i])) <= 0) out.add(pts[i - 1] * R, pts[i] * R);
      }
      return;
    }
  }
}


// Distance from (px, py) to the segment a-b.
double segment_distance(double px, double py, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double qx = px - ax, qy = py - ay;
  const double len2 = ex * ex + ey * ey;
  const double t = len2 > 0 ? std::clamp((qx * ex + qy * ey) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(qx - t * ex, qy - t * ey);
}

// Exact distance of an extrusion: 2D distance d2 of the section, |z| - half depth dz.
double extrusion_distance(double d2, double dz) {
  return std::min(std::max(d2, dz), 0.0) + std::hypot(std::max(d2, 0.0), std::max(dz, 0.0));
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
  throw std::invalid_argument("unknown 3D primitive '" + std::string(name) +
                              "' (expected box, sphere, cylinder, cone, ellipsoid, torus or prism)");
}

PrimitiveSet3D PrimitiveSet3D::all() {
  PrimitiveSet3D s;
  for (int i = 0; i <= static_cast<int>(PrimitiveKind3D::TriangularPrism); ++i)
    s.add(static_cast<PrimitiveKind3D>(i));
  return s;
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

// ---------------------------------------------------------------------------------------------
// Primitive3D

namespace {
Primitive3D make(PrimitiveKind3D kind, double cx, double cy, double cz, const Quaternion& q,
                 Vec3 dims, double apex = 0) {
  Primitive3D p;
  p.kind = kind;
  p.cx = cx, p.cy = cy, p.cz = cz;
  p.rotation = q;
  p.dims = dims;
  p.apex = apex;
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

double Primitive3D::volume() const {
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
  const Vec3 l = to_local(x, y, z);
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
      const double rho = std::hypot(l[0], l[1]) - d[0];
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
  }
  return false;
}

double Primitive3D::signed_distance(double x, double y, double z) const {
  const Vec3 l = to_local(x, y, z);
  const Vec3& d = dims;
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
      return extrusion_distance(std::hypot(l[0], l[1]) - d[0], std::fabs(l[2]) - d[2] / 2);
    case PrimitiveKind3D::Cone: {
      // A solid of revolution: the distance in the meridian half-plane (rho, z) to the profile
      // (bottom edge, slanted side, top edge; the axis is not a surface) is the 3D distance.
      const double rho = std::hypot(l[0], l[1]), h = d[2] / 2;
      const double dist = std::min({segment_distance(rho, l[2], 0, -h, d[0], -h),
                                    segment_distance(rho, l[2], d[0], -h, d[1], h),
                                    segment_distance(rho, l[2], d[1], h, 0, h)});
      return contains(x, y, z) ? -dist : dist;
    }
    case PrimitiveKind3D::Torus:
      return std::hypot(std::hypot(l[0], l[1]) - d[0], l[2]) - d[1];
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
    default:
      for (double& v : dims) v = std::max(v, kMinSize);
      break;
  }
  if (kind == PrimitiveKind3D::TriangularPrism)
    apex = std::isfinite(apex) ? std::clamp(apex, -kMaxApex, kMaxApex) : 0.0;
  else
    apex = 0;
}

bool Primitive3D::operator==(const Primitive3D& o) const {
  return kind == o.kind && cx == o.cx && cy == o.cy && cz == o.cz && rotation == o.rotation &&
         dims == o.dims && apex == o.apex;
}

// ---------------------------------------------------------------------------------------------
// Scan conversion

void rasterize(const Primitive3D& p, VoxelGrid& out) {
  out.clear();
  rasterize_into(p, out);
}

void rasterize_into(const Primitive3D& p, VoxelGrid& out) {
  if (out.empty()) return;
  const Bounds3 box = p.bounds();
  const double vs = out.voxel_size();
  const double org[3] = {out.origin_x(), out.origin_y(), out.origin_z()};
  const int n[3] = {out.nx(), out.ny(), out.nz()};
  // Index range of the voxel centres inside [lo, hi] along each axis.
  int first[3], last[3];
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box.lo[a]) || !std::isfinite(box.hi[a])) return;  // NaN draws nothing
    const double f = std::ceil((box.lo[a] - org[a]) / vs - 0.5 - 1e-9);
    const double l = std::floor((box.hi[a] - org[a]) / vs - 0.5 + 1e-9);
    first[a] = static_cast<int>(std::clamp(f, 0.0, static_cast<double>(n[a])));
    last[a] = static_cast<int>(std::clamp(l, -1.0, static_cast<double>(n[a] - 1)));
    if (first[a] > last[a]) return;
  }
  const Mat3 m = p.rotation.matrix();
  // local = R^T (x - c): along an x-row the local point moves by R^T e_x = row 0 of R.
  const Vec3 u{m[0][0], m[0][1], m[0][2]};
  const double nx_d = static_cast<double>(n[0] - 1);
  for (int k = first[2]; k <= last[2]; ++k) {
    const double dz = out.center_z(k) - p.cz;
    for (int j = first[1]; j <= last[1]; ++j) {
      const double dy = out.center_y(j) - p.cy;
      const Vec3 b{m[1][0] * dy + m[2][0] * dz, m[1][1] * dy + m[2][1] * dz,
                   m[1][2] * dy + m[2][2] * dz};
      Spans spans;
      line_spans(p, u, b, spans);
      for (int s = 0; s < spans.n; ++s) {
        // Voxel i is inside when its centre org + (i + 0.5) vs lies in [cx + lo, cx + hi].
        const double i0 = std::ceil((p.cx + spans.iv[s].lo - org[0]) / vs - 0.5);
        const double i1 = std::floor((p.cx + spans.iv[s].hi - org[0]) / vs - 0.5);
        const double c0 = std::max(i0, 0.0), c1 = std::min(i1, nx_d);
        if (c0 <= c1) out.set_span(j, k, static_cast<int>(c0), static_cast<int>(c1) + 1);
      }
    }
  }
}

}  // namespace csgfit
