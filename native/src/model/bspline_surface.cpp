// B-spline bases and tensor-product surfaces: Piegl and Tiller's span search (A2.1) and
// Cox-de Boor triangle (A2.2) with first derivatives (A2.3, first order only).
#include "csgfit/model/bspline_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "model/linalg.h"

namespace csgfit {

namespace {

double clamp01(double u) { return std::isnan(u) ? 0.0 : std::clamp(u, 0.0, 1.0); }

std::vector<double> open_uniform_knots(int count, int degree) {
  std::vector<double> t(static_cast<std::size_t>(count + degree + 1), 0.0);
  const int interior = count - degree - 1;
  for (int k = 1; k <= interior; ++k) t[degree + k] = static_cast<double>(k) / (interior + 1);
  std::fill(t.end() - (degree + 1), t.end(), 1.0);
  return t;
}

}  // namespace

BSplineBasis::BSplineBasis(int count, int degree) : degree_(degree), count_(count) {
  if (degree < 1 || degree > kMaxBSplineDegree || count <= degree)
    throw std::invalid_argument("B-spline: need 1 <= degree <= " +
                                std::to_string(kMaxBSplineDegree) + " and more control points "
                                "than the degree");
  knots_ = open_uniform_knots(count, degree);
}

BSplineBasis::BSplineBasis(std::vector<double> knots, int degree)
    : knots_(std::move(knots)), degree_(degree),
      count_(static_cast<int>(knots_.size()) - degree - 1) {
  check();
}

// A clamped vector: ends at 0 and 1 with multiplicity degree + 1, interior knots inside and
// at most degree-fold (a (degree + 1)-fold interior knot would split the surface in two).
void BSplineBasis::check() const {
  const auto bad = [](const char* why) { throw std::invalid_argument(std::string("knot vector: ") + why); };
  if (degree_ < 1 || degree_ > kMaxBSplineDegree || count_ <= degree_) bad("wrong degree or length");
  for (int k = 0; k <= degree_; ++k)
    if (knots_[k] != 0.0 || knots_[count_ + k] != 1.0) bad("not clamped to [0, 1]");
  for (std::size_t k = 1; k < knots_.size(); ++k)
    if (!(knots_[k] >= knots_[k - 1])) bad("not non-decreasing");
  for (int k = degree_ + 1; k < count_; ++k)
    if (!(knots_[k] > 0.0 && knots_[k] < 1.0)) bad("an interior knot at an end");
  for (int k = degree_ + 1; k + degree_ < count_; ++k)
    if (knots_[k + degree_] == knots_[k]) bad("an interior knot repeats more than degree times");
}

int BSplineBasis::span(double u) const {
  u = clamp01(u);
  if (u >= knots_[count_]) return count_ - 1;
  // The last s with t_s <= u among s = degree .. count - 1.
  const auto it = std::upper_bound(knots_.begin() + degree_, knots_.begin() + count_, u);
  return static_cast<int>(it - knots_.begin()) - 1;
}

BasisAt BSplineBasis::at(double u) const {
  u = clamp01(u);
  const int s = span(u), p = degree_;
  BasisAt b;
  b.first = s - p;
  std::array<double, kMaxBSplineDegree + 1> left{}, right{}, lower{};
  auto& n = b.value;
  n[0] = 1;
  for (int k = 1; k <= p; ++k) {
    if (k == p) lower = n;  // the degree p - 1 functions, for the derivatives
    left[k] = u - knots_[s + 1 - k];
    right[k] = knots_[s + k] - u;
    double saved = 0;
    for (int r = 0; r < k; ++r) {
      const double temp = n[r] / (right[r + 1] + left[k - r]);
      n[r] = saved + right[r + 1] * temp;
      saved = left[k - r] * temp;
    }
    n[k] = saved;
  }
  // N'_i,p = p (N_i,p-1 / (t_i+p - t_i) - N_i+1,p-1 / (t_i+p+1 - t_i+1)); the nonzero degree
  // p - 1 functions are N_{s-p+1 .. s} = lower[0 .. p-1].
  for (int r = 0; r <= p; ++r) {
    const int i = b.first + r;
    const double a = r > 0 ? lower[r - 1] / (knots_[i + p] - knots_[i]) : 0.0;
    const double c = r < p ? lower[r] / (knots_[i + p + 1] - knots_[i + 1]) : 0.0;
    b.slope[r] = p * (a - c);
  }
  return b;
}

double BSplineBasis::greville(int i) const {
  double sum = 0;
  for (int k = 1; k <= degree_; ++k) sum += knots_[i + k];
  return sum / degree_;
}

BSplineSurface::BSplineSurface(BSplineBasis u_basis, BSplineBasis v_basis, std::vector<Vec3> net)
    : u_(std::move(u_basis)), v_(std::move(v_basis)), net_(std::move(net)) {
  if (net_.size() != static_cast<std::size_t>(u_.count()) * v_.count())
    throw std::invalid_argument("B-spline surface: the control net must have nu x nv vertices");
}

namespace {

bool finite_rectangle(const XYRectangle& r) {
  return std::isfinite(r.x0) && std::isfinite(r.x1) && r.x1 > r.x0 && std::isfinite(r.y0) &&
         std::isfinite(r.y1) && r.y1 > r.y0;
}

std::vector<double> columns(const BSplineBasis& b, double lo, double hi, NetSpacing spacing) {
  std::vector<double> out(static_cast<std::size_t>(b.count()));
  for (int i = 0; i < b.count(); ++i) {
    const double t = spacing == NetSpacing::Greville ? b.greville(i)
                                                     : static_cast<double>(i) / (b.count() - 1);
    out[i] = lo + (hi - lo) * t;
  }
  out.back() = hi;  // the end columns are the rectangle's sides, not a rounding of them
  return out;
}

bool increasing(const std::vector<double>& c) {
  for (std::size_t i = 0; i < c.size(); ++i)
    if (!std::isfinite(c[i]) || (i > 0 && !(c[i] > c[i - 1]))) return false;
  return true;
}

// Whether columns stand at the Greville abscissae, where the coordinate is linear in u and the
// inversion is one division (bitwise the same as before columns could move).
bool at_greville(const BSplineBasis& b, const std::vector<double>& c) {
  const double lo = c.front(), hi = c.back(), tol = 1e-12 * (hi - lo);
  for (int i = 0; i < b.count(); ++i)
    if (std::fabs(c[i] - (lo + (hi - lo) * b.greville(i))) > tol) return false;
  return true;
}

// u with x(u) = sum_i N_i(u) c_i = x. Strictly increasing columns make x(u) strictly increasing
// (its derivative is a positive combination of column differences), so Newton from the linear
// guess, kept inside the bracket it shrinks, cannot leave [0, 1] or cycle.
double invert_coordinate(const BSplineBasis& b, const std::vector<double>& c, double x) {
  const double lo = c.front(), hi = c.back();
  if (!(x > lo)) return 0.0;  // NaN too, as clamp01 does
  if (!(x < hi)) return 1.0;
  double a = 0, z = 1, u = (x - lo) / (hi - lo);
  for (int it = 0; it < 60 && z - a > 1e-16; ++it) {
    const BasisAt at = b.at(u);
    double f = -x, slope = 0;
    for (int r = 0; r <= b.degree(); ++r) {
      f += at.value[r] * c[at.first + r];
      slope += at.slope[r] * c[at.first + r];
    }
    if (std::fabs(f) <= 1e-14 * (hi - lo)) break;
    (f > 0 ? z : a) = u;
    const double next = slope > 0 ? u - f / slope : 0.5 * (a + z);
    u = next > a && next < z ? next : 0.5 * (a + z);
  }
  return u;
}

}  // namespace

BSplineSurface BSplineSurface::height_field(BSplineBasis u_basis, BSplineBasis v_basis,
                                            const XYRectangle& rect,
                                            const std::vector<double>& heights,
                                            NetSpacing spacing) {
  if (!finite_rectangle(rect))
    throw std::invalid_argument("B-spline height field: the x-y rectangle is empty or not finite");
  std::vector<double> xs = columns(u_basis, rect.x0, rect.x1, spacing);
  std::vector<double> ys = columns(v_basis, rect.y0, rect.y1, spacing);
  return height_field(std::move(u_basis), std::move(v_basis), std::move(xs), std::move(ys), heights);
}

BSplineSurface BSplineSurface::height_field(BSplineBasis u_basis, BSplineBasis v_basis,
                                            std::vector<double> xs, std::vector<double> ys,
                                            const std::vector<double>& heights) {
  const int nu = u_basis.count(), nv = v_basis.count();
  if (xs.size() != static_cast<std::size_t>(nu) || ys.size() != static_cast<std::size_t>(nv) ||
      !increasing(xs) || !increasing(ys))
    throw std::invalid_argument("B-spline height field: control columns and rows must be finite "
                                "and strictly increasing, one per control point");
  if (heights.size() != static_cast<std::size_t>(nu) * nv)
    throw std::invalid_argument("B-spline height field: need nu x nv control heights");
  std::vector<Vec3> net(heights.size());
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) net[i + nu * j] = {xs[i], ys[j], heights[i + nu * j]};
  BSplineSurface s(std::move(u_basis), std::move(v_basis), std::move(net));
  s.rect_ = {xs.front(), xs.back(), ys.front(), ys.back()};
  s.linear_x_ = at_greville(s.u_, xs);
  s.linear_y_ = at_greville(s.v_, ys);
  s.xs_ = std::move(xs);
  s.ys_ = std::move(ys);
  return s;
}

SurfaceFrame BSplineSurface::frame(double u, double v) const {
  const BasisAt bu = u_.at(u), bv = v_.at(v);
  SurfaceFrame f;
  for (int b = 0; b <= v_.degree(); ++b) {
    const int j = bv.first + b;
    for (int a = 0; a <= u_.degree(); ++a) {
      const Vec3& c = control_point(bu.first + a, j);
      const double w = bu.value[a] * bv.value[b], wu = bu.slope[a] * bv.value[b],
                   wv = bu.value[a] * bv.slope[b];
      for (int k = 0; k < 3; ++k) {
        f.point[k] += w * c[k];
        f.du[k] += wu * c[k];
        f.dv[k] += wv * c[k];
      }
    }
  }
  f.normal = linalg::normalized(linalg::cross(f.du, f.dv));
  return f;
}

Vec3 BSplineSurface::point(double u, double v) const { return frame(u, v).point; }

std::array<double, 2> BSplineSurface::parameters_of(double x, double y) const {
  return {linear_x_ ? clamp01((x - rect_.x0) / (rect_.x1 - rect_.x0)) : invert_coordinate(u_, xs_, x),
          linear_y_ ? clamp01((y - rect_.y0) / (rect_.y1 - rect_.y0)) : invert_coordinate(v_, ys_, y)};
}

double BSplineSurface::height_at(double x, double y) const { return frame_at(x, y).point[2]; }

SurfaceFrame BSplineSurface::frame_at(double x, double y) const {
  const auto uv = parameters_of(x, y);
  return frame(uv[0], uv[1]);
}

}  // namespace csgfit
