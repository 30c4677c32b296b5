// Internal to features/: what the RANSAC of boundary arcs and of boundary segments share.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "csgfit/features/boundary_curves.h"
#include "model/random.h"

namespace csgfit::contour_ransac {

/// A curve with the side the shape lies on (+1: inside it, a disc; -1: outside, a hole) and
/// the votes it drew.
template <typename Curve>
struct SignedHypothesis {
  Curve curve;
  int sign = 0;
  std::size_t votes = 0;
};

/// A sample's anchor, drawn from `active`, and in `near` the active points within a window of
/// `base` * 2^k px of it (k drawn from 0..3, so that small and large features are both sampled).
inline const ContourPoint& draw_neighbourhood(const std::vector<ContourPoint>& pts,
                                              const std::vector<std::size_t>& active, double base,
                                              rnd::Rng& rng, std::vector<std::size_t>& near) {
  const ContourPoint& a = pts[active[rnd::pick(rng, active.size())]];
  const double window = base * std::pow(2.0, static_cast<double>(rnd::pick(rng, 4)));
  near.clear();
  for (std::size_t i : active)
    if (std::hypot(pts[i].x - a.x, pts[i].y - a.y) <= window) near.push_back(i);
  return a;
}

/// Every how many active points a hypothesis's votes are counted: at most about 800 counted.
inline std::size_t vote_stride(const std::vector<std::size_t>& active) {
  return active.size() / 800 > 1 ? active.size() / 800 : 1;
}

/// The fraction of a closed curve that the longest run of `angles` (its parameter, radians)
/// spans, in `bins` bins (at least 8, at most 720) with gaps of two bins bridged: scattered
/// points on several edges make no arc.
inline double longest_run(const std::vector<double>& angles, double bins_wanted) {
  constexpr double kTurn = 2 * 3.14159265358979323846;
  const std::size_t bins = static_cast<std::size_t>(std::clamp(bins_wanted, 8.0, 720.0));
  std::vector<bool> seen(bins, false);
  for (double a : angles) {
    const double t = std::fmod(std::fmod(a, kTurn) + kTurn, kTurn) / kTurn;
    seen[std::min(bins - 1, static_cast<std::size_t>(t * static_cast<double>(bins)))] = true;
  }
  const auto first_empty = std::find(seen.begin(), seen.end(), false);
  if (first_empty == seen.end()) return 1.0;
  // Walk once around from an empty bin, so that a run over the seam is one run.
  const std::size_t start = static_cast<std::size_t>(first_empty - seen.begin());
  std::size_t longest = 0, run = 0, gap = 0;
  for (std::size_t s = 1; s <= bins; ++s) {
    if (seen[(start + s) % bins]) {
      run += (run > 0 ? gap : 0) + 1, gap = 0;
      longest = std::max(longest, run);
    } else if (++gap > 2) {
      run = 0, gap = 0;
    }
  }
  return static_cast<double>(longest) / static_cast<double>(bins);
}

/// A curve's inliers among `active` at tolerances of 0.75, 0.5 and 0.4 px (`on_curve(i,
/// tolerance)`), the curve refitted to them after each (`refit(on)`; false keeps the last fit);
/// fewer than `least` inliers stop the tightening.
template <typename OnCurve, typename Refit>
std::vector<std::size_t> tightened_inliers(const std::vector<std::size_t>& active, std::size_t least,
                                           OnCurve on_curve, Refit refit) {
  std::vector<std::size_t> on;
  for (double tolerance : {0.75, 0.5, 0.4}) {
    on.clear();
    for (std::size_t i : active)
      if (on_curve(i, tolerance)) on.push_back(i);
    if (on.size() < least || !refit(on)) break;
  }
  return on;
}

/// The sequential RANSAC the readings share. Each round takes the best hypothesis on the points
/// no earlier round used (`hypothesise(active)`: nothing ends the search), grows it into its
/// inliers (`inliers(hypothesis, active)`, which may refine it in place), marks those used
/// whether or not `read(hypothesis, inliers)` accepts them as a reading (what looked like an arc
/// and is none is not tried again), and stops at `limit` readings or 2 `limit` rounds.
template <typename Reading, typename Hypothesise, typename Inliers, typename Read>
std::vector<Reading> sequential(std::size_t points, std::size_t limit, std::size_t min_active,
                                Hypothesise hypothesise, Inliers inliers, Read read) {
  std::vector<bool> used(points, false);
  std::vector<Reading> out;
  for (std::size_t round = 0; round < 2 * limit && out.size() < limit; ++round) {
    std::vector<std::size_t> active;
    for (std::size_t i = 0; i < points; ++i)
      if (!used[i]) active.push_back(i);
    if (active.size() < min_active) break;
    auto hypothesis = hypothesise(active);
    if (!hypothesis) break;
    const std::vector<std::size_t> on = inliers(*hypothesis, active);
    for (std::size_t i : on) used[i] = true;
    if (std::optional<Reading> r = read(*hypothesis, on)) out.push_back(*r);
  }
  return out;
}

}  // namespace csgfit::contour_ransac
