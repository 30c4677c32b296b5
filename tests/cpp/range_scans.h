// Range scans rendered from a known tree through a camera, for the tests of the range stages.
#pragma once

#include <cmath>
#include <vector>

#include "csgfit/eval/range_view.h"
#include "csgfit/model/range_scan.h"
#include "csgfit/model/tree3d.h"

namespace csgfit::testing {

/// What `camera` sees of `tree`: a return per pixel whose ray meets it, with the exact outward
/// normal there.
inline RangeScan scan_of(const Node3D& tree, const RangeCamera& camera) {
  RangeScan scan;
  scan.camera = camera;
  scan.width = camera.width, scan.height = camera.height;
  const std::vector<double> depth = tree_depth_map(tree, camera, 1e-5);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const double d = depth[static_cast<std::size_t>(v) * camera.width + u];
      if (d <= 0) continue;
      const Vec3 p = camera.world_point(u, v, d);
      scan.points.push_back(p);
      scan.pixel.push_back(v * camera.width + u);
      const double h = 1e-6;
      const Vec3 g{signed_distance(tree, p[0] + h, p[1], p[2]) - signed_distance(tree, p[0] - h, p[1], p[2]),
                   signed_distance(tree, p[0], p[1] + h, p[2]) - signed_distance(tree, p[0], p[1] - h, p[2]),
                   signed_distance(tree, p[0], p[1], p[2] + h) - signed_distance(tree, p[0], p[1], p[2] - h)};
      const double n = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      scan.normals.push_back({g[0] / n, g[1] / n, g[2] / n});
    }
  return scan;
}

/// An orthographic camera of `size` x `size` pixels of `pixel` units looking at `target` from
/// the direction (azimuth, elevation) in degrees, `distance` away.
inline RangeCamera looking_at(const Vec3& target, double azimuth, double elevation, double distance,
                              int size, double pixel) {
  const double a = azimuth * M_PI / 180, e = elevation * M_PI / 180;
  const Vec3 from{std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  const Vec3 z{-from[0], -from[1], -from[2]};  // the view direction
  Vec3 x{-std::sin(a), std::cos(a), 0};        // right
  const Vec3 y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
  RangeCamera c;
  c.projection = Projection::Orthographic;
  c.width = c.height = size;
  c.pixel_size = pixel;
  c.cx = c.cy = size / 2.0;
  const Vec3 origin{target[0] + distance * from[0], target[1] + distance * from[1],
                    target[2] + distance * from[2]};
  for (int r = 0; r < 3; ++r) {
    c.camera_to_world[4 * r + 0] = x[r];
    c.camera_to_world[4 * r + 1] = y[r];
    c.camera_to_world[4 * r + 2] = z[r];
    c.camera_to_world[4 * r + 3] = origin[r];
  }
  return c;
}

}  // namespace csgfit::testing
