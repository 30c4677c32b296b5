#include "model/roots.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace csgfit::roots {

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace csgfit::roots
