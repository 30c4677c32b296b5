// Internal to model/: intervals of a line parameter, narrowed by linear constraints: what the
// 2D and 3D scan conversions intersect a row with.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace csgfit::interval {

/// [lo, hi]; empty when lo > hi (or NaN).
struct Interval {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool empty() const { return !(lo <= hi); }
};

/// Narrows `iv` to the s where lo <= a*s + b <= hi.
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

/// Narrows `iv` to the s where a*s + b >= 0.
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

}  // namespace csgfit::interval
