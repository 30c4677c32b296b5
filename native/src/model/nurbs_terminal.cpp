#include "model/nurbs_terminal.h"

#include <algorithm>
#include <cmath>

namespace csgfit::nurbs {

namespace {

// 6-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree 11, so for a bicubic patch
// that stays above its floor (times its quadratic Jacobian) the volume is exact per knot span.
constexpr double kNodes[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                              0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
constexpr double kWeights[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                0.4679139345726910, 0.3607615730481386, 0.1713244923791704};

// The distinct knots of a basis: the spans a quadrature must not straddle.
std::vector<double> breaks(const BSplineBasis& b) {
  std::vector<double> out;
  for (double k : b.knots())
    if (out.empty() || k > out.back()) out.push_back(k);
  return out;
}

}  // namespace

bool contains(const Primitive3D& p, const Vec3& l) {
  const Vec3& d = p.dims;
  if (std::fabs(l[0]) > d[0] / 2 || std::fabs(l[1]) > d[1] / 2 || l[2] < 0) return false;
  return l[2] <= p.patch->height_at(l[0], l[1]);
}

double signed_distance(const Primitive3D& p, const Vec3& l) {
  const Vec3& d = p.dims;
  // The prism over the rectangle from the floor up, without a top: a box of infinite height.
  const double qx = std::fabs(l[0]) - d[0] / 2, qy = std::fabs(l[1]) - d[1] / 2, qz = -l[2];
  const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0), std::max(qz, 0.0));
  const double prism = outside + std::min(std::max({qx, qy, qz}), 0.0);
  const SurfaceFrame f = p.patch->frame_at(l[0], l[1]);
  // normal.z = 1 / sqrt(1 + |grad S|^2) for a height field.
  const double top = (l[2] - f.point[2]) * std::max(f.normal[2], 1e-6);
  return std::max(prism, top);
}

double volume(const Primitive3D& p) {
  const BSplineSurface& s = *p.patch;
  const std::vector<double> bu = breaks(s.u_basis()), bv = breaks(s.v_basis());
  double total = 0;
  for (std::size_t a = 0; a + 1 < bu.size(); ++a)
    for (std::size_t b = 0; b + 1 < bv.size(); ++b) {
      const double u0 = bu[a], u1 = bu[a + 1], v0 = bv[b], v1 = bv[b + 1];
      double span = 0;
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          const double u = u0 + (u1 - u0) * (kNodes[i] + 1) / 2;
          const double v = v0 + (v1 - v0) * (kNodes[j] + 1) / 2;
          // dx dy = x'(u) y'(v) du dv: x depends on u alone and y on v alone.
          const SurfaceFrame f = s.frame(u, v);
          span += kWeights[i] * kWeights[j] * std::max(f.point[2], 0.0) * f.du[0] * f.dv[1];
        }
      total += span * (u1 - u0) * (v1 - v0) / 4;
    }
  return total;
}

Vec3 dims_of(const BSplineSurface& patch) {
  const XYRectangle& r = patch.rectangle();
  double top = 0;
  for (const Vec3& v : patch.net()) top = std::max(top, v[2]);
  return {r.x1 - r.x0, r.y1 - r.y0, top};
}

bool same_patch(const BSplineSurface* a, const BSplineSurface* b) {
  if (a == b) return true;
  if (!a || !b) return false;
  return a->u_basis().degree() == b->u_basis().degree() &&
         a->v_basis().degree() == b->v_basis().degree() &&
         a->u_basis().knots() == b->u_basis().knots() &&
         a->v_basis().knots() == b->v_basis().knots() && a->net() == b->net();
}

}  // namespace csgfit::nurbs
