// Scan conversion of the 3D primitives: per x-row of voxel centres, the analytic interval(s)
// of the primitive on that line (one for convex kinds, the rounded box included, up to two for
// the torus).
#include <algorithm>
#include <cmath>

#include "csgfit/model/primitive3d.h"
#include "model/interval.h"
#include "model/polygonal_solid.h"
#include "model/prism_triangle.h"
#include "model/roots.h"
#include "model/rounded_box.h"

namespace csgfit {

namespace {

using interval::clip_halfline;
using interval::clip_linear;
using interval::Interval;
using roots::poly_eval;
using roots::torus_roots;

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

// The torus of line_spans (dims d): a quartic in the line parameter.
void torus_spans(const Vec3& d, const Vec3& u, const Vec3& b, Spans& out) {
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
}

// The line x -> (x, y, z) in p's local frame is local(s) = u * s + b with s = x - cx.
// Appends the s-intervals inside p.
void line_spans(const Primitive3D& p, const Vec3& u, const Vec3& b, Spans& out) {
  const Vec3& d = p.dims;
  if (p.is_polygonal()) {
    Interval iv;
    polygonal::clip_line(p, u, b, iv);
    out.add(iv.lo, iv.hi);
    return;
  }
  switch (p.kind) {
    case PrimitiveKind3D::Nurbs: return;  // rasterize_by_centres
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
    case PrimitiveKind3D::Torus:
      torus_spans(d, u, b, out);
      return;
    case PrimitiveKind3D::RoundedBox: {
      const Interval iv = rounded_box::line_interval(p, u, b);
      out.add(iv.lo, iv.hi);
      return;
    }
  }
}

// A line may cross a free-form patch any number of times, more than Spans holds: the NURBS
// terminal is tested at each voxel centre of its bounds, runs set at once.
void rasterize_by_centres(const Primitive3D& p, const int first[3], const int last[3],
                          VoxelGrid& out) {
  for (int k = first[2]; k <= last[2]; ++k)
    for (int j = first[1]; j <= last[1]; ++j) {
      int run = -1;
      for (int i = first[0]; i <= last[0] + 1; ++i) {
        const bool in = i <= last[0] && p.contains(out.center_x(i), out.center_y(j), out.center_z(k));
        if (in && run < 0) run = i;
        if (!in && run >= 0) out.set_span(j, k, run, i), run = -1;
      }
    }
}

// The NURBS terminal on the line local(t) = u t + b: along the local vertical its column is
// [0, S(x, y)] at once; any other line is sampled at 256 steps over the bounds and each
// crossing bisected to 1e-9 of the step.
void nurbs_spans(const Primitive3D& p, const Vec3& u, const Vec3& b, Spans& out) {
  const Vec3& d = p.dims;
  if (std::fabs(u[0]) < 1e-12 && std::fabs(u[1]) < 1e-12) {
    if (std::fabs(b[0]) > d[0] / 2 || std::fabs(b[1]) > d[1] / 2) return;
    const double top = p.patch->height_at(b[0], b[1]);
    if (top < 0) return;
    Interval iv;
    clip_linear(iv, u[2], b[2], 0, top);
    out.add(iv.lo, iv.hi);
    return;
  }
  double low = 0;
  for (const Vec3& v : p.patch->net()) low = std::min(low, v[2]);
  Interval iv;
  clip_linear(iv, u[0], b[0], -d[0] / 2, d[0] / 2);
  clip_linear(iv, u[1], b[1], -d[1] / 2, d[1] / 2);
  clip_linear(iv, u[2], b[2], low, d[2]);
  if (iv.empty() || !std::isfinite(iv.lo) || !std::isfinite(iv.hi)) return;
  auto inside = [&](double t) {
    const Vec3 l{u[0] * t + b[0], u[1] * t + b[1], u[2] * t + b[2]};
    return l[2] >= 0 && std::fabs(l[0]) <= d[0] / 2 && std::fabs(l[1]) <= d[1] / 2 &&
           l[2] <= p.patch->height_at(l[0], l[1]);
  };
  auto crossing = [&](double a, double c, bool a_in) {
    for (int k = 0; k < 40; ++k) {
      const double m = 0.5 * (a + c);
      (inside(m) == a_in ? a : c) = m;
    }
    return 0.5 * (a + c);
  };
  const int steps = 256;
  const double h = (iv.hi - iv.lo) / steps;
  bool was = inside(iv.lo);
  double start = iv.lo;
  for (int i = 1; i <= steps; ++i) {
    const double t = iv.lo + i * h;
    const bool now = inside(t);
    if (now != was) {
      const double x = crossing(t - h, t, was);
      if (now) start = x; else out.add(start, x);
      was = now;
    }
  }
  if (was) out.add(start, iv.hi);
}

}  // namespace

int line_intervals(const Primitive3D& p, const Vec3& o, const Vec3& d, double lo[4], double hi[4]) {
  const Mat3 m = p.rotation.matrix();
  const Vec3 rel{o[0] - p.cx, o[1] - p.cy, o[2] - p.cz};
  Vec3 u{}, b{};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) u[j] += m[i][j] * d[i], b[j] += m[i][j] * rel[i];
  Spans spans;
  if (p.kind == PrimitiveKind3D::Nurbs)
    nurbs_spans(p, u, b, spans);
  else
    line_spans(p, u, b, spans);
  for (int i = 0; i < spans.n; ++i) lo[i] = spans.iv[i].lo, hi[i] = spans.iv[i].hi;
  return spans.n;
}

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
  if (p.kind == PrimitiveKind3D::Nurbs) return rasterize_by_centres(p, first, last, out);
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
