// Internal to refine/: Levenberg-Marquardt on one primitive's parameters against points of the
// input's boundary, written once for 2D primitives (contour points) and 3D ones (surface
// samples). The parameters are those the local optimiser moves (Moves2D, Moves3D).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "csgfit/refine/local_opt.h"

namespace csgfit::least_squares {

/// Solves the n x n system a x = b in place by Gaussian elimination with partial pivoting;
/// false when it is singular.
inline bool solve(std::vector<double>& a, std::vector<double>& b, int n) {
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(a[r * n + c]) > std::fabs(a[piv * n + c])) piv = r;
    if (!(std::fabs(a[piv * n + c]) > 1e-300)) return false;
    if (piv != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[piv * n + k]);
      std::swap(b[c], b[piv]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (int c = n - 1; c >= 0; --c) {
    double v = b[c];
    for (int k = c + 1; k < n; ++k) v -= a[c * n + k] * b[k];
    b[c] = v / a[c * n + c];
  }
  return true;
}

/// The primitive whose boundary passes closest to `pts` in the least-squares sense, from
/// `start`: `residual(p, point)` is the point's signed distance to p's boundary, `unit` the
/// grid step (derivatives are taken over a hundredth of it; no step moves a parameter by more
/// than two of it, as the linearisation holds no further).
template <typename Moves, typename Prim, typename Point, typename Residual>
Prim fit_to_points(const Moves& moves, const Prim& start, const std::vector<const Point*>& pts,
                   double unit, int iterations, Residual residual) {
  typename Moves::Param params[Moves::kMaxParams];
  const int np = moves.params_of(start, LocalOptOptions{}, params);
  const std::size_t m = pts.size();
  auto sum_squares = [&](const Prim& p) {
    double s = 0;
    for (const Point* q : pts) {
      const double d = residual(p, *q);
      s += d * d;
    }
    return s;
  };
  Prim p = start;
  double cost = sum_squares(p);
  double lambda = 1e-3;
  const double eps = 0.01 * unit;
  std::vector<double> r(m), jac(m * static_cast<std::size_t>(np));
  for (int it = 0; it < iterations && cost > 0; ++it) {
    for (std::size_t i = 0; i < m; ++i) r[i] = residual(p, *pts[i]);
    for (int j = 0; j < np; ++j) {
      Prim q = p;
      moves.move(q, params[j], eps);
      q.normalize();
      for (std::size_t i = 0; i < m; ++i) jac[i * np + j] = (residual(q, *pts[i]) - r[i]) / eps;
    }
    std::vector<double> jtj(static_cast<std::size_t>(np * np), 0.0), jtr(static_cast<std::size_t>(np), 0.0);
    for (std::size_t i = 0; i < m; ++i)
      for (int a = 0; a < np; ++a) {
        const double ja = jac[i * np + a];
        if (ja == 0) continue;
        jtr[a] -= ja * r[i];
        for (int b = 0; b < np; ++b) jtj[a * np + b] += ja * jac[i * np + b];
      }
    bool stepped = false;
    for (int tries = 0; tries < 6 && !stepped; ++tries) {
      std::vector<double> a = jtj, b = jtr;
      for (int d = 0; d < np; ++d) a[d * np + d] += lambda * std::max(jtj[d * np + d], 1e-12);
      if (!solve(a, b, np)) {
        lambda *= 10;
        continue;
      }
      Prim q = p;
      for (int j = 0; j < np; ++j) moves.move(q, params[j], std::clamp(b[j], -2 * unit, 2 * unit));
      q.normalize();
      const double c = sum_squares(q);
      if (c < cost) {
        p = q;
        stepped = cost - c > 1e-9 * cost;
        cost = c;
        lambda = std::max(lambda / 3, 1e-9);
        if (!stepped) return p;
      } else {
        lambda *= 4;
      }
    }
    if (!stepped) break;
  }
  return p;
}

}  // namespace csgfit::least_squares
