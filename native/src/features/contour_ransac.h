// Internal to features/: what the RANSAC of boundary arcs and of boundary segments share.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "csgfit/features/boundary_curves.h"
#include "model/random.h"

namespace csgfit::contour_ransac {

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

}  // namespace csgfit::contour_ransac
