#include "csgfit/eval/range_view.h"

#include <algorithm>
#include <cmath>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

// What the tree can occupy: its positive leaves' bounds (a difference's cuts add nothing).
void occupied(const Node3D& n, Bounds3& b, bool& any) {
  if (n.is_leaf()) {
    if (!any) b = n.primitive.bounds(), any = true;
    else b = merged(b, n.primitive.bounds());
    return;
  }
  if (n.kind == NodeKind::Difference) {
    if (!n.children.empty()) occupied(n.children.front(), b, any);
    return;
  }
  for (const Node3D& c : n.children) occupied(c, b, any);
}

double sdf(const Node3D& tree, const Vec3& p) { return signed_distance(tree, p[0], p[1], p[2]); }

}  // namespace

std::vector<double> tree_depth_map(const Node3D& tree, const RangeCamera& camera,
                                   double tolerance) {
  std::vector<double> depth(static_cast<std::size_t>(camera.width) * camera.height, 0.0);
  Bounds3 box;
  bool any = false;
  occupied(tree, box, any);
  if (!any) return depth;
  for (int i = 0; i < 3; ++i) box.lo[i] -= tolerance, box.hi[i] += tolerance;
  const Vec3 view = camera.view_direction();
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const Vec3 o = camera.ray_origin(u, v), d = camera.ray_direction(u, v);
      double t, t_end;
      if (!clip_ray(box, o, d, t, t_end)) continue;
      for (int step = 0; step < 512 && t <= t_end; ++step) {
        const double s = sdf(tree, add(o, scale(d, t)));
        if (s < tolerance) {
          depth[static_cast<std::size_t>(v) * camera.width + u] = t * dot(d, view);
          break;
        }
        t += std::max(s, 0.5 * tolerance);
      }
    }
  return depth;
}

DepthAgreement compare_depth(const RangeScan& scan, const std::vector<double>& tree_depth) {
  DepthAgreement a;
  if (!scan.camera || !scan.organised()) return a;
  std::vector<double> seen(tree_depth.size(), 0.0);
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    seen[scan.pixel[i]] = scan.camera->project(scan.points[i])[2];
  double sum = 0;
  for (std::size_t px = 0; px < seen.size(); ++px) {
    const bool s = seen[px] > 0, h = tree_depth[px] > 0;
    a.seen += s, a.hit += h;
    if (s && h) ++a.both, sum += std::abs(seen[px] - tree_depth[px]);
  }
  const std::size_t either = a.seen + a.hit - a.both;
  a.silhouette_iou = either ? static_cast<double>(a.both) / static_cast<double>(either) : 1.0;
  a.mean_depth_error = a.both ? sum / static_cast<double>(a.both) : 0.0;
  return a;
}

}  // namespace csgfit
