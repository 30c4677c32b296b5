#include "csgfit/features/point_normals.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "features/cloud_normals.h"
#include "model/linalg.h"

namespace csgfit {

namespace {

using linalg::cross;
using linalg::dot;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_unit(Vec3& v) {
  const double len = std::sqrt(dot(v, v));
  if (!(len > 1e-300) || !std::isfinite(len)) return false;
  for (double& c : v) c /= len;
  return true;
}

Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// An organised scan's points by pixel: grid[v * width + u] is the point's index, or -1.
std::vector<int> pixel_grid(const RangeScan& scan) {
  std::vector<int> grid(static_cast<std::size_t>(scan.width) * scan.height, -1);
  for (std::size_t i = 0; i < scan.pixel.size(); ++i) grid[scan.pixel[i]] = static_cast<int>(i);
  return grid;
}

// How wide one pixel is on a surface facing the sensor, per point: the camera says so; without
// one, the median distance between a point and its nearest 4-neighbour stands for all.
std::vector<double> footprints(const RangeScan& scan, const std::vector<int>& grid) {
  std::vector<double> fp(scan.points.size());
  if (scan.camera) {
    const RangeCamera& c = *scan.camera;
    for (std::size_t i = 0; i < fp.size(); ++i) {
      fp[i] = c.projection == Projection::Orthographic
                  ? c.pixel_size
                  : std::abs(c.project(scan.points[i])[2]) / std::sqrt(c.fx * c.fy);
    }
    return fp;
  }
  std::vector<double> nearest;
  nearest.reserve(fp.size());
  for (std::size_t i = 0; i < fp.size(); ++i) {
    const int u = scan.pixel[i] % scan.width, v = scan.pixel[i] / scan.width;
    double best = std::numeric_limits<double>::infinity();
    const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
    for (int d = 0; d < 4; ++d) {
      const int uu = u + du[d], vv = v + dv[d];
      if (uu < 0 || vv < 0 || uu >= scan.width || vv >= scan.height) continue;
      const int j = grid[static_cast<std::size_t>(vv) * scan.width + uu];
      if (j < 0) continue;
      const Vec3 e = minus(scan.points[j], scan.points[i]);
      best = std::min(best, std::sqrt(dot(e, e)));
    }
    if (std::isfinite(best) && best > 0) nearest.push_back(best);
  }
  double median = 0;
  if (!nearest.empty()) {
    std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
    median = nearest[nearest.size() / 2];
  }
  std::fill(fp.begin(), fp.end(), median);
  return fp;
}

// The plane through point i's continuous window: the normal of least variance, turned to
// point against the image's du x dv (towards a sensor with x right and y down); NaN when the
// window's pixels are collinear or its points coincide.
Vec3 window_normal(const RangeScan& scan, const std::vector<int>& grid,
                   const std::vector<double>& fp, std::size_t i,
                   const PointNormalOptions& options) {
  const int u = scan.pixel[i] % scan.width, v = scan.pixel[i] / scan.width;
  const Vec3& p = scan.points[i];
  const int r = std::max(1, options.window_radius);
  Vec3 sum{0, 0, 0}, tu{0, 0, 0}, tv{0, 0, 0};
  double su2 = 0, sv2 = 0, suv = 0;
  std::vector<Vec3> window;
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= scan.width || vv >= scan.height) continue;
      const int j = grid[static_cast<std::size_t>(vv) * scan.width + uu];
      if (j < 0) continue;
      const Vec3 e = minus(scan.points[j], p);
      const double reach = options.max_jump * fp[i] * std::sqrt(double(du * du + dv * dv));
      if (dot(e, e) > reach * reach) continue;
      window.push_back(e);
      for (int c = 0; c < 3; ++c) {
        sum[c] += e[c];
        tu[c] += e[c] * du;
        tv[c] += e[c] * dv;
      }
      su2 += du * du, sv2 += dv * dv, suv += du * dv;
    }
  }
  // Pixel offsets on one line leave the plane's tilt about that line unknown.
  if (su2 * sv2 - suv * suv < 0.5) return {kNaN, kNaN, kNaN};
  const double count = static_cast<double>(window.size());
  Mat3 cov{};
  for (const Vec3& e : window) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) cov[a][b] += (e[a] - sum[a] / count) * (e[b] - sum[b] / count);
  }
  Vec3 values;
  Mat3 vectors;
  symmetric_eigen3(cov, values, vectors);
  if (!(values[1] > 0)) return {kNaN, kNaN, kNaN};
  Vec3 n = linalg::column(vectors, 2);
  if (dot(n, cross(tu, tv)) > 0) n = {-n[0], -n[1], -n[2]};
  return is_unit(n) ? n : Vec3{kNaN, kNaN, kNaN};
}

// Towards the camera pixel by pixel; else towards the given view, or away from the centroid
// as a whole (the image's orientation is consistent, only its sign is unknown).
void orient_organised(const RangeScan& scan, const PointNormalOptions& options,
                      std::vector<Vec3>& normals) {
  const auto flip = [&](std::size_t i) {
    for (double& c : normals[i]) c = -c;
  };
  if (scan.camera || options.view_direction) {
    for (std::size_t i = 0; i < normals.size(); ++i) {
      const int u = scan.pixel[i] % scan.width, v = scan.pixel[i] / scan.width;
      const Vec3 ray = scan.camera ? scan.camera->ray_direction(u, v) : *options.view_direction;
      if (dot(normals[i], ray) > 0) flip(i);
    }
    return;
  }
  Vec3 centroid{0, 0, 0};
  for (const Vec3& p : scan.points)
    for (int c = 0; c < 3; ++c) centroid[c] += p[c] / static_cast<double>(scan.points.size());
  double outward = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (std::isfinite(normals[i][0])) outward += dot(normals[i], minus(scan.points[i], centroid));
  }
  if (outward < 0)
    for (std::size_t i = 0; i < normals.size(); ++i) flip(i);
}

std::vector<Vec3> organised_normals(const RangeScan& scan, const PointNormalOptions& options) {
  const std::vector<int> grid = pixel_grid(scan);
  const std::vector<double> fp = footprints(scan, grid);
  std::vector<Vec3> normals(scan.points.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    normals[i] = window_normal(scan, grid, fp, i, options);
  }
  orient_organised(scan, options, normals);
  return normals;
}

// Keeps the points with a unit normal, in order.
void drop_points_without_normals(RangeScan& scan) {
  std::size_t kept = 0;
  const bool organised = scan.pixel.size() == scan.points.size();
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!is_unit(scan.normals[i])) continue;
    scan.points[kept] = scan.points[i];
    scan.normals[kept] = scan.normals[i];
    if (organised) scan.pixel[kept] = scan.pixel[i];
    ++kept;
  }
  scan.dropped_outliers += scan.points.size() - kept;
  scan.points.resize(kept);
  scan.normals.resize(kept);
  if (organised) scan.pixel.resize(kept);
}

}  // namespace

void complete_normals(RangeScan& scan, const PointNormalOptions& options) {
  if (scan.normals.size() != scan.points.size()) {
    const bool by_pixel = scan.organised() && scan.pixel.size() == scan.points.size();
    scan.normals = by_pixel ? organised_normals(scan, options)
                            : features_detail::cloud_normals(scan.points, options.neighbours,
                                                             options.outlier_spacing);
  }
  drop_points_without_normals(scan);
}

}  // namespace csgfit
