#include "csgfit/refine/nurbs_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace csgfit {

namespace {

constexpr int kSizes[] = {4, 5, 6, 7, 8, 10, 12, 15, 18, 24};
// Sparse scans (the seed's 8 x 24 points under 15 x 4 vertices) leave room between the rows for
// a net to wiggle: the bending weight is chosen with the net, on the same held-out points.
constexpr double kSmoothings[] = {1e-8, 1e-6, 1e-5, 1e-4};
// Greville columns make x linear in u; equally spaced ones are how a designer draws a control
// polygon, and between sparse sample rows the two bend differently: the held-out points choose.
constexpr NetSpacing kSpacings[] = {NetSpacing::Greville, NetSpacing::Uniform};

double rms_on(const BSplineSurface& s, const std::vector<Vec3>& points) {
  double sum = 0;
  for (const Vec3& p : points) {
    const double e = s.height_at(p[0], p[1]) - p[2];
    sum += e * e;
  }
  return points.empty() ? 0 : std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace

PatchFit fit_height_patch(const std::vector<Vec3>& points, double floor) {
  if (points.size() < 20) throw std::invalid_argument("a NURBS patch needs at least 20 points");
  const Bounds3 box = bounds_of(points);
  const double cx = 0.5 * (box.lo[0] + box.hi[0]), cy = 0.5 * (box.lo[1] + box.hi[1]);
  const XYRectangle rect{box.lo[0] - cx, box.hi[0] - cx, box.lo[1] - cy, box.hi[1] - cy};
  if (!(rect.x1 > rect.x0 && rect.y1 > rect.y0))
    throw std::invalid_argument("the points do not span an x-y rectangle");
  std::vector<Vec3> local, train, test;
  for (std::size_t i = 0; i < points.size(); ++i) {
    local.push_back({points[i][0] - cx, points[i][1] - cy, points[i][2] - floor});
    (i % 5 == 4 ? test : train).push_back(local.back());
  }
  const std::size_t most = points.size() / 3;
  int best_u = 0, best_v = 0;
  double best = std::numeric_limits<double>::infinity(), best_smoothing = kSmoothings[0];
  NetSpacing best_spacing = NetSpacing::Greville;
  std::size_t best_size = 0;
  for (NetSpacing spacing : kSpacings)
    for (int nu : kSizes)
      for (int nv : kSizes)
        for (double smoothing : kSmoothings) {
          const std::size_t size = static_cast<std::size_t>(nu * nv);
          if (size > most) continue;
          try {
            const HeightFit f = fit_heights(train, rect, nu, nv, 3, 3, smoothing, spacing);
            const double e = rms_on(f.surface, test);
            // Of two nets that predict as well, the smaller is the one a designer would edit.
            const bool better = e < best * (size < best_size ? 1.02 : size > best_size ? 0.98 : 1.0);
            if (best_u == 0 || better)
              best = e, best_u = nu, best_v = nv, best_size = size, best_smoothing = smoothing,
              best_spacing = spacing;
          } catch (const std::invalid_argument&) {
            // A net the training points do not determine is no candidate.
          }
        }
  if (best_u == 0) throw std::invalid_argument("no control net fits the points");
  HeightFit all = fit_heights(local, rect, best_u, best_v, 3, 3, best_smoothing, best_spacing);
  PatchFit out{Primitive3D::nurbs(cx, cy, floor, all.surface), best_u, best_v, best_spacing,
               all.rms, best};
  return out;
}

}  // namespace csgfit
