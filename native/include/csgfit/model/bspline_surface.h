// Tensor-product B-spline surfaces (seed 004, Sec. 2.3-2.4): the sculptured face of a
// CSG-NURBS hybrid. The seed's NURBS terminal is a height field z = S(x, y) over an x-y
// rectangle, the solid everything below it; here that is a non-rational B-spline (all weights
// 1) with clamped knot vectors. Its control columns stand at fixed x (rows at fixed y): at the
// Greville abscissae of the rectangle, where x and y are exactly linear in u and v (linear
// precision), or at any strictly increasing positions (equally spaced ones are the control
// polygon a designer draws), where x(u) is a monotone spline inverted per point. The net is kept
// as full 3D control points.
// Algorithms are Piegl and Tiller's (The NURBS Book, A2.1-A2.3); no Eigen in this header.
#pragma once

#include <array>
#include <vector>

#include "csgfit/model/quaternion.h"

namespace csgfit {

/// The largest degree a basis accepts (fixed-size work arrays: no allocation per evaluation).
constexpr int kMaxBSplineDegree = 7;

/// The p + 1 basis functions of degree p that may be nonzero at one parameter: N_{first + r, p}
/// for r = 0 .. p, and their first derivatives dN/du.
struct BasisAt {
  int first = 0;
  std::array<double, kMaxBSplineDegree + 1> value{};
  std::array<double, kMaxBSplineDegree + 1> slope{};
};

/// One direction of a tensor-product B-spline: the degree, the number of control points and a
/// clamped knot vector on [0, 1] (the first and last knots repeated degree + 1 times, as the
/// seed's U and V), so that the curve starts and ends at its end control points.
class BSplineBasis {
 public:
  /// Open uniform knots: degree + 1 zeros, count - degree - 1 equally spaced interior knots,
  /// degree + 1 ones. Throws std::invalid_argument unless 1 <= degree <= kMaxBSplineDegree and
  /// count > degree.
  BSplineBasis(int count, int degree);
  /// Any clamped knot vector on [0, 1] of count + degree + 1 non-decreasing knots whose interior
  /// knots repeat at most degree times; throws std::invalid_argument otherwise.
  BSplineBasis(std::vector<double> knots, int degree);

  int degree() const { return degree_; }
  int count() const { return count_; }
  const std::vector<double>& knots() const { return knots_; }
  /// The knot span [t_s, t_s+1) holding u (clamped to [0, 1]); u = 1 falls in the last one.
  int span(double u) const;
  /// Cox-de Boor: the nonzero basis functions at u (clamped to [0, 1]) and their derivatives.
  BasisAt at(double u) const;
  /// Greville abscissa of control point i: the mean of its degree interior knots. Placing
  /// control points there makes the curve's coordinate equal to u (linear precision).
  double greville(int i) const;

 private:
  void check() const;
  std::vector<double> knots_;
  int degree_ = 3, count_ = 4;
};

/// A point of the surface with its partial derivatives and unit normal (Su x Sv normalised; for
/// a height field over x0 < x1, y0 < y1 it points up, +z, out of the solid below).
struct SurfaceFrame {
  Vec3 point{}, du{}, dv{}, normal{};
};

/// The x-y rectangle a height field covers: u = 0..1 is x = x0..x1, v = 0..1 is y = y0..y1.
struct XYRectangle {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
};

/// Where a height field's control columns stand along x (and its rows along y).
enum class NetSpacing {
  Greville,  ///< at the Greville abscissae: x = x0 + (x1 - x0) u exactly
  Uniform,   ///< equally spaced from x0 to x1: x(u) is a monotone spline, not linear
};

/// S(u, v) = sum_ij N_i,p(u) N_j,q(v) P_ij over the control net P (nu x nv vertices, u index
/// fastest: P_ij = net[i + nu * j]).
class BSplineSurface {
 public:
  BSplineSurface(BSplineBasis u_basis, BSplineBasis v_basis, std::vector<Vec3> net);
  /// The height field over `rect` with control heights h (nu x nv, u index fastest): vertex
  /// (i, j) at (x_i, y_j, h_ij), the columns x_i and rows y_j placed by `spacing`. Throws
  /// std::invalid_argument when the rectangle is empty or not finite, or h has the wrong size.
  static BSplineSurface height_field(BSplineBasis u_basis, BSplineBasis v_basis,
                                     const XYRectangle& rect, const std::vector<double>& heights,
                                     NetSpacing spacing = NetSpacing::Greville);
  /// The height field whose control columns stand at x = xs[i] and rows at y = ys[j] (strictly
  /// increasing, finite, nu and nv of them), over [xs.front, xs.back] x [ys.front, ys.back].
  static BSplineSurface height_field(BSplineBasis u_basis, BSplineBasis v_basis,
                                     std::vector<double> xs, std::vector<double> ys,
                                     const std::vector<double>& heights);

  const BSplineBasis& u_basis() const { return u_; }
  const BSplineBasis& v_basis() const { return v_; }
  const std::vector<Vec3>& net() const { return net_; }
  std::vector<Vec3>& net() { return net_; }
  const Vec3& control_point(int i, int j) const { return net_[i + u_.count() * j]; }
  /// The rectangle of a height field (what height_field was given; the unit square otherwise).
  const XYRectangle& rectangle() const { return rect_; }
  /// A height field's column positions x_i and row positions y_j (empty otherwise).
  const std::vector<double>& columns_x() const { return xs_; }
  const std::vector<double>& rows_y() const { return ys_; }

  Vec3 point(double u, double v) const;
  SurfaceFrame frame(double u, double v) const;
  /// Height field only: z = S(x, y) and the frame there, (x, y) clamped to the rectangle.
  double height_at(double x, double y) const;
  SurfaceFrame frame_at(double x, double y) const;
  /// (u, v) with S(u, v) above (x, y), clamped to [0, 1]^2: straight from (x, y) on Greville
  /// columns, by a safeguarded Newton iteration on x(u) and y(v) otherwise.
  std::array<double, 2> parameters_of(double x, double y) const;

 private:
  BSplineBasis u_, v_;
  std::vector<Vec3> net_;
  XYRectangle rect_;
  std::vector<double> xs_, ys_;
  bool linear_x_ = true, linear_y_ = true;  // columns / rows at the Greville abscissae
};

/// What fit_heights returns: the surface and how far the points are from it along z.
struct HeightFit {
  BSplineSurface surface;
  double rms = 0, max_residual = 0;
};

/// Least-squares fit of a height field's control heights to scattered points (x, y, z): nu x nv
/// control points of degree p x q over `rect`, minimising
///   sum_k (S(x_k, y_k) - z_k)^2 + lambda |D h|^2,
/// where D takes the second divided differences of the heights along u and along v over the
/// control columns (rows) and lambda = smoothing x trace(A^T A) / trace(D^T D) (so `smoothing` is
/// free of the point count and the rectangle's size). Points outside the rectangle are clamped
/// onto its border. Throws std::invalid_argument on non-finite points or a bad size, and when the
/// points do not determine the net (smoothing 0 and an unsupported control point, or fewer than
/// four points not on a line).
HeightFit fit_heights(const std::vector<Vec3>& points, const XYRectangle& rect, int nu, int nv,
                      int p = 3, int q = 3, double smoothing = 1e-6,
                      NetSpacing spacing = NetSpacing::Greville);
/// The same over the points' own x-y bounding box (throws when it is empty in x or y).
HeightFit fit_heights(const std::vector<Vec3>& points, int nu, int nv, int p = 3, int q = 3,
                      double smoothing = 1e-6);

}  // namespace csgfit
