#include "csgfit/features/range_evidence.h"

#include <algorithm>
#include <cmath>

#include "csgfit/model/primitive3d.h"
#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

// Offsets in front of a return, in tolerances: close ones pin the surface, far ones keep
// hidden extents from reaching into what the sensor saw through.
constexpr double kInFront[] = {2, 5, 12, 30};

void in_front_of_returns(const RangeScan& scan, std::size_t stride, double tol, RangeEvidence& e) {
  for (std::size_t i = 0; i < scan.points.size(); i += stride) {
    Vec3 towards_sensor;
    if (scan.camera && scan.organised()) {
      const int px = scan.pixel[i];
      towards_sensor = scale(scan.camera->ray_direction(px % scan.width + 0.0, px / scan.width + 0.0), -1);
    } else if (!scan.normals.empty()) {
      towards_sensor = scan.normals[i];
    } else {
      continue;
    }
    for (double k : kInFront) e.empty.push_back(add(scan.points[i], scale(towards_sensor, k * tol)));
  }
}

// Rays that returned nothing but cross the part's box: empty all along.
void through_misses(const RangeScan& scan, const Bounds3& box, std::size_t budget, RangeEvidence& e) {
  if (!scan.camera || !scan.organised()) return;
  std::vector<char> returned(static_cast<std::size_t>(scan.width) * scan.height, 0);
  for (int px : scan.pixel) returned[px] = 1;
  std::vector<int> misses;
  for (std::size_t px = 0; px < returned.size(); ++px) {
    if (returned[px]) continue;
    const double u = static_cast<double>(px % scan.width), v = static_cast<double>(px / scan.width);
    double t0, t1;
    if (clip_ray(box, scan.camera->ray_origin(u, v), scan.camera->ray_direction(u, v), t0, t1))
      misses.push_back(static_cast<int>(px));
  }
  constexpr int kAlongRay = 6;
  const std::size_t stride = std::max<std::size_t>(1, misses.size() * kAlongRay / std::max<std::size_t>(1, budget));
  for (std::size_t m = 0; m < misses.size(); m += stride) {
    const double u = static_cast<double>(misses[m] % scan.width);
    const double v = static_cast<double>(misses[m] / scan.width);
    const Vec3 o = scan.camera->ray_origin(u, v), d = scan.camera->ray_direction(u, v);
    double t0, t1;
    clip_ray(box, o, d, t0, t1);
    for (int k = 0; k < kAlongRay; ++k)
      e.empty.push_back(add(o, scale(d, t0 + (t1 - t0) * (k + 0.5) / kAlongRay)));
  }
}

}  // namespace

RangeEvidence gather_evidence(const std::vector<RangeScan>& scans, double tolerance,
                              std::size_t max_surface) {
  RangeEvidence e;
  e.tolerance = tolerance;
  std::size_t total = 0;
  Bounds3 box{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (const RangeScan& s : scans) {
    total += s.points.size();
    if (!s.points.empty()) box = merged(box, bounds_of(s.points));
  }
  for (int i = 0; i < 3; ++i) box.lo[i] -= 2 * tolerance, box.hi[i] += 2 * tolerance;
  const std::size_t stride = std::max<std::size_t>(1, total / std::max<std::size_t>(1, max_surface));
  for (const RangeScan& s : scans) {
    for (std::size_t i = 0; i < s.points.size(); i += stride) e.surface.push_back(s.points[i]);
    // A quarter of the empty points in front of returns, the rest through misses.
    in_front_of_returns(s, stride * 2, tolerance, e);
    through_misses(s, box, max_surface / scans.size(), e);
  }
  return e;
}

}  // namespace csgfit
