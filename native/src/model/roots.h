// Internal to model/: real roots of small polynomials, for the line-torus intersections of
// the 3D scan conversion.
#pragma once

namespace csgfit::roots {

/// Value of c[0] + c[1] s + ... + c[deg] s^deg.
double poly_eval(const double* c, int deg, double s);

/// Real roots of the polynomial in (a, b), sorted, found through the roots of its derivative
/// (which split [a, b] into monotone pieces), recursively down to a line. Returns the count.
int roots_in(const double* c, int deg, double a, double b, double* out);

/// Real roots in (lo, hi) of the quartic c[0] + c[1] s + ... + c[4] s^4, sorted: Ferrari's
/// closed form, each root polished by a Newton step, roots_in as the fallback.
int torus_roots(const double* c, double lo, double hi, double* out);

}  // namespace csgfit::roots
