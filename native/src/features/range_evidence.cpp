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

// Half a tolerance behind every `stride`-th return, along its inward normal. A return seen at a
// grazing angle sits on an edge or a silhouette, where the image's normals blur: skipped.
void behind_returns(const RangeScan& scan, std::size_t stride, double tol, RangeEvidence& e) {
  if (scan.normals.size() != scan.points.size()) return;
  const bool rays = scan.camera && scan.organised();
  for (std::size_t i = 0; i < scan.points.size(); i += stride) {
    const Vec3& n = scan.normals[i];
    if (rays) {
      const int px = scan.pixel[i];
      const Vec3 ray = scan.camera->ray_direction(px % scan.width + 0.0, px / scan.width + 0.0);
      if (-dot(ray, n) < 0.3) continue;
    }
    e.behind.push_back(add(scan.points[i], scale(n, -0.5 * tol)));
  }
}

// Pixels within `reach` pixels (chessboard distance) of a return: the band around the
// silhouette where a tree a little too large shows.
std::vector<char> near_returns(const std::vector<char>& returned, int width, int height, int reach) {
  std::vector<char> near = returned;
  for (int pass = 0; pass < reach; ++pass) {
    std::vector<char> grown = near;
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) {
        if (near[static_cast<std::size_t>(v) * width + u]) continue;
        for (int dv = -1; dv <= 1; ++dv)
          for (int du = -1; du <= 1; ++du) {
            const int uu = u + du, vv = v + dv;
            if (uu >= 0 && vv >= 0 && uu < width && vv < height && near[static_cast<std::size_t>(vv) * width + uu])
              grown[static_cast<std::size_t>(v) * width + u] = 1;
          }
      }
    near.swap(grown);
  }
  return near;
}

void along_ray(const RangeScan& scan, int px, const Bounds3& box, int count, RangeEvidence& e) {
  const double u = static_cast<double>(px % scan.width), v = static_cast<double>(px / scan.width);
  const Vec3 o = scan.camera->ray_origin(u, v), d = scan.camera->ray_direction(u, v);
  double t0, t1;
  if (!clip_ray(box, o, d, t0, t1)) return;
  for (int k = 0; k < count; ++k) e.empty.push_back(add(o, scale(d, t0 + (t1 - t0) * (k + 0.5) / count)));
}

// Rays that returned nothing but cross the part's box: empty all along. Every ray near the
// silhouette (where a tree a little too large shows, and the silhouette IoU counts each pixel
// alike), the others as `budget` allows.
void through_misses(const RangeScan& scan, const Bounds3& box, std::size_t budget, RangeEvidence& e) {
  if (!scan.camera || !scan.organised()) return;
  std::vector<char> returned(static_cast<std::size_t>(scan.width) * scan.height, 0);
  for (int px : scan.pixel) returned[px] = 1;
  constexpr int kBand = 5, kAlongRay = 6;
  const std::vector<char> band = near_returns(returned, scan.width, scan.height, kBand);
  std::vector<int> far;
  for (std::size_t px = 0; px < returned.size(); ++px) {
    if (returned[px]) continue;
    if (band[px]) {
      along_ray(scan, static_cast<int>(px), box, kAlongRay, e);
      continue;
    }
    const double u = static_cast<double>(px % scan.width), v = static_cast<double>(px / scan.width);
    double t0, t1;
    if (clip_ray(box, scan.camera->ray_origin(u, v), scan.camera->ray_direction(u, v), t0, t1))
      far.push_back(static_cast<int>(px));
  }
  // Every other ray through the box too, more sparsely along it: a primitive hanging out of
  // the part where nothing returned must cost about what the silhouette loses by it.
  constexpr int kAlongFarRay = 3;
  const std::size_t stride = std::max<std::size_t>(1, far.size() * kAlongFarRay / std::max<std::size_t>(1, budget));
  for (std::size_t m = 0; m < far.size(); m += stride) along_ray(scan, far[m], box, kAlongFarRay, e);
}

// A view's return depth per pixel (0 = none): what its camera says of any point of space.
struct DepthView {
  const RangeCamera& camera;
  std::vector<double> depth;

  explicit DepthView(const RangeScan& scan)
      : camera(*scan.camera), depth(static_cast<std::size_t>(scan.width) * scan.height, 0.0) {
    for (std::size_t i = 0; i < scan.points.size(); ++i) depth[scan.pixel[i]] = camera.project(scan.points[i])[2];
  }
  // Whether the view saw `p` to be empty: on a ray with no return, or in front of its return.
  bool sees_empty(const Vec3& p, double tolerance) const {
    const Vec3 uvd = camera.project(p);
    const long u = std::lround(uvd[0]), v = std::lround(uvd[1]);
    if (!(uvd[2] > 0) || u < 0 || v < 0 || u >= camera.width || v >= camera.height) return false;
    const double seen = depth[static_cast<std::size_t>(v) * camera.width + u];
    return seen <= 0 || uvd[2] < seen - tolerance;
  }
};

// Lattice points of the box that every view has behind its surface (about `budget` lattice
// points tried). A view without a camera cannot say what it hid: then there are none.
void hidden_points(const std::vector<RangeScan>& scans, const Bounds3& box, std::size_t budget,
                   double tolerance, RangeEvidence& e) {
  std::vector<DepthView> views;
  for (const RangeScan& s : scans) {
    if (!s.camera || !s.organised()) return;
    views.emplace_back(s);
  }
  double volume = 1;
  for (int a = 0; a < 3; ++a) volume *= box.hi[a] - box.lo[a];
  const double step = std::cbrt(volume / static_cast<double>(std::max<std::size_t>(1, budget)));
  if (!(step > 0)) return;
  for (double x = box.lo[0] + step / 2; x < box.hi[0]; x += step)
    for (double y = box.lo[1] + step / 2; y < box.hi[1]; y += step)
      for (double z = box.lo[2] + step / 2; z < box.hi[2]; z += step) {
        const Vec3 p{x, y, z};
        if (std::none_of(views.begin(), views.end(), [&](const DepthView& v) { return v.sees_empty(p, tolerance); }))
          e.hidden.push_back(p);
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
  // Rays that returned nothing are empty beyond the points' box too, where a primitive may
  // hang out of the part (a slab reaching past a plate's edge): the misses are sampled over a
  // box a tenth of the part's size wider on every side. Hidden points stay in the points' box.
  Bounds3 reach = box;
  double diagonal = 0;
  for (int i = 0; i < 3; ++i) diagonal += (box.hi[i] - box.lo[i]) * (box.hi[i] - box.lo[i]);
  diagonal = std::sqrt(diagonal);
  for (int i = 0; i < 3; ++i) {
    box.lo[i] -= 2 * tolerance, box.hi[i] += 2 * tolerance;
    reach.lo[i] -= 0.1 * diagonal, reach.hi[i] += 0.1 * diagonal;
  }
  const std::size_t stride = std::max<std::size_t>(1, total / std::max<std::size_t>(1, max_surface));
  for (const RangeScan& s : scans) {
    for (std::size_t i = 0; i < s.points.size(); i += stride) e.surface.push_back(s.points[i]);
    // A quarter of the empty points in front of returns, the rest through misses.
    in_front_of_returns(s, stride * 2, tolerance, e);
    behind_returns(s, stride * 2, tolerance, e);
    through_misses(s, reach, 6 * max_surface / scans.size(), e);
  }
  hidden_points(scans, box, 2 * max_surface, tolerance, e);
  for (const RangeScan& s : scans)
    if (s.camera) e.cameras.push_back(*s.camera);
  return e;
}

bool faces_away_from_every_view(const RangeEvidence& evidence, const Vec3& point, const Vec3& normal) {
  constexpr double kAway = 0.087;  // sin 5 degrees
  for (const RangeCamera& c : evidence.cameras) {
    const Vec3 origin{c.camera_to_world[3], c.camera_to_world[7], c.camera_to_world[11]};
    const Vec3 ray = c.projection == Projection::Pinhole ? normalized(sub(point, origin)) : c.view_direction();
    if (dot(ray, normal) < kAway) return false;
  }
  return !evidence.cameras.empty();
}

}  // namespace csgfit
