// Least squares of a height field's control heights to scattered points: the local optimiser of
// a NURBS terminal (issue 14), the sparse normal equations on Eigen's LDL^T.
#include "csgfit/model/bspline_surface.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace csgfit {

namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

void check_points(const std::vector<Vec3>& points) {
  if (points.size() < 4) throw std::invalid_argument("B-spline fit: need at least four points");
  for (const Vec3& p : points)
    if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
      throw std::invalid_argument("B-spline fit: a point is not finite");
}

// The collocation matrix A: row k holds N_i,p(u_k) N_j,q(v_k) in column i + nu j, so that
// A h is the height field at the points.
Sparse collocation(const BSplineSurface& s, const std::vector<Vec3>& points) {
  const BSplineBasis &bu = s.u_basis(), &bv = s.v_basis();
  Triplets t;
  t.reserve(points.size() * static_cast<std::size_t>((bu.degree() + 1) * (bv.degree() + 1)));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto uv = s.parameters_of(points[k][0], points[k][1]);
    const BasisAt a = bu.at(uv[0]), b = bv.at(uv[1]);
    for (int jb = 0; jb <= bv.degree(); ++jb)
      for (int ia = 0; ia <= bu.degree(); ++ia)
        t.emplace_back(static_cast<int>(k), a.first + ia + bu.count() * (b.first + jb),
                       a.value[ia] * b.value[jb]);
  }
  Sparse m(static_cast<Eigen::Index>(points.size()), bu.count() * bv.count());
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

// Rows of D along one direction: second divided differences of the heights over the control
// columns' positions (so that the penalty approximates the integral of z_xx^2 + z_yy^2 in model
// units, the same in x and in y). Divided differences, not plain ones, because the columns are
// not equally spaced (Greville abscissae crowd at clamped ends): a plane has zero penalty only
// with the divided ones.
void second_differences(const std::vector<double>& at, int lines, int stride_along,
                        int stride_across, Triplets& t, int& row) {
  for (int line = 0; line < lines; ++line)
    for (std::size_t i = 1; i + 1 < at.size(); ++i) {
      const double g0 = at[i - 1], g1 = at[i], g2 = at[i + 1];
      const double w0 = 2 / ((g1 - g0) * (g2 - g0)), w2 = 2 / ((g2 - g1) * (g2 - g0));
      const int c = static_cast<int>(i) * stride_along + line * stride_across;
      t.emplace_back(row, c - stride_along, w0);
      t.emplace_back(row, c, -(w0 + w2));
      t.emplace_back(row, c + stride_along, w2);
      ++row;
    }
}

Sparse smoothing_operator(const BSplineSurface& s) {
  const int nu = s.u_basis().count(), nv = s.v_basis().count();
  Triplets t;
  int rows = 0;
  second_differences(s.columns_x(), nv, 1, nu, t, rows);
  second_differences(s.rows_y(), nu, nu, 1, t, rows);
  Sparse d(rows, nu * nv);
  d.setFromTriplets(t.begin(), t.end());
  return d;
}

// Solves (A^T A + lambda D^T D) h = A^T z. Without the smoothing a control point with no point
// under its support (a gap in the scan, a sparse blade of 8 x 24 points under 4 x 15 vertices)
// makes A^T A singular; the second differences carry the neighbouring slope into the gap
// instead, and their null space (heights bilinear in the vertex positions) is fixed by any four
// points not on a line. A zero pivot is reported rather than solved through.
Eigen::VectorXd solve_heights(const Sparse& a, const Eigen::VectorXd& z, const Sparse& d,
                              double smoothing) {
  Sparse n = Sparse(a.transpose()) * a;
  if (smoothing > 0 && d.rows() > 0) {
    const Sparse dd = Sparse(d.transpose()) * d;
    const double ratio = n.diagonal().sum() / dd.diagonal().sum();
    n += (smoothing * ratio) * dd;
  }
  Eigen::SimplicialLDLT<Sparse> ldlt(n);
  const auto pivots = ldlt.vectorD();
  if (ldlt.info() != Eigen::Success || !(pivots.minCoeff() > 1e-12 * pivots.maxCoeff()))
    throw std::invalid_argument("B-spline fit: the points do not determine the control net");
  return ldlt.solve(a.transpose() * z);
}

}  // namespace

HeightFit fit_heights(const std::vector<Vec3>& points, const XYRectangle& rect, int nu, int nv,
                      int p, int q, double smoothing, NetSpacing spacing) {
  check_points(points);
  if (!(smoothing >= 0) || !std::isfinite(smoothing))
    throw std::invalid_argument("B-spline fit: smoothing must be finite and >= 0");
  BSplineBasis bu(nu, p), bv(nv, q);
  BSplineSurface s = BSplineSurface::height_field(
      bu, bv, rect, std::vector<double>(static_cast<std::size_t>(nu) * nv, 0.0), spacing);
  const Sparse a = collocation(s, points);
  Eigen::VectorXd z(static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k) z[static_cast<Eigen::Index>(k)] = points[k][2];
  const Eigen::VectorXd h = solve_heights(a, z, smoothing_operator(s), smoothing);
  for (Eigen::Index c = 0; c < h.size(); ++c) s.net()[c][2] = h[c];
  const Eigen::VectorXd r = a * h - z;
  return {std::move(s), std::sqrt(r.squaredNorm() / static_cast<double>(r.size())),
          r.cwiseAbs().maxCoeff()};
}

HeightFit fit_heights(const std::vector<Vec3>& points, int nu, int nv, int p, int q,
                      double smoothing) {
  check_points(points);
  XYRectangle r{points[0][0], points[0][0], points[0][1], points[0][1]};
  for (const Vec3& pt : points) {
    r.x0 = std::min(r.x0, pt[0]);
    r.x1 = std::max(r.x1, pt[0]);
    r.y0 = std::min(r.y0, pt[1]);
    r.y1 = std::max(r.y1, pt[1]);
  }
  if (!(r.x1 > r.x0 && r.y1 > r.y0))
    throw std::invalid_argument("B-spline fit: the points span no area in x and y");
  return fit_heights(points, r, nu, nv, p, q, smoothing);
}

}  // namespace csgfit
