#include "features/point_neighbours.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace csgfit::features_detail {

PointNeighbours::PointNeighbours(const std::vector<Vec3>& points) : points_(points) {
  box_ = bounds_of(points);
  double volume = 1;
  int dims = 0;
  for (int a = 0; a < 3; ++a) {
    const double e = box_.hi[a] - box_.lo[a];
    if (e > 0) volume *= e, ++dims;
  }
  const double per_cell = 2.0 / static_cast<double>(points.size());
  cell_ = dims == 0 ? 1 : std::pow(volume * per_cell, 1.0 / dims);
  // A surface fills a 3D box thinly: cells sized for a volume would hold too many points.
  if (dims == 3) cell_ = std::sqrt(volume / std::max({box_.hi[0] - box_.lo[0], box_.hi[1] - box_.lo[1], box_.hi[2] - box_.lo[2]}) * per_cell);
  cell_ = std::max(cell_, 1e-12);
  for (int a = 0; a < 3; ++a)
    n_[a] = std::max(1LL, static_cast<long long>(std::ceil((box_.hi[a] - box_.lo[a]) / cell_)) + 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    long long c[3];
    cell_of(points[i], c);
    cells_[key(c[0], c[1], c[2])].push_back(i);
  }
}

long long PointNeighbours::key(long long i, long long j, long long k) const {
  return i + n_[0] * (j + n_[1] * k);
}

void PointNeighbours::cell_of(const Vec3& p, long long c[3]) const {
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<long long>(std::floor((p[a] - box_.lo[a]) / cell_)), 0LL, n_[a] - 1);
}

std::vector<std::size_t> PointNeighbours::nearest(const Vec3& q, std::size_t k) const {
  k = std::min(k, points_.size());
  long long c[3];
  cell_of(q, c);
  std::vector<std::pair<double, std::size_t>> found;
  const long long most = std::max({n_[0], n_[1], n_[2]});
  for (long long ring = 0; ring <= most; ++ring) {
    for (long long i = c[0] - ring; i <= c[0] + ring; ++i)
      for (long long j = c[1] - ring; j <= c[1] + ring; ++j)
        for (long long l = c[2] - ring; l <= c[2] + ring; ++l) {
          if (std::max({std::llabs(i - c[0]), std::llabs(j - c[1]), std::llabs(l - c[2])}) != ring) continue;
          if (i < 0 || j < 0 || l < 0 || i >= n_[0] || j >= n_[1] || l >= n_[2]) continue;
          const auto it = cells_.find(key(i, j, l));
          if (it == cells_.end()) continue;
          for (std::size_t p : it->second) {
            double d = 0;
            for (int a = 0; a < 3; ++a) d += (points_[p][a] - q[a]) * (points_[p][a] - q[a]);
            found.push_back({d, p});
          }
        }
    // Everything within ring cells of q's cell is found; a point beyond is at least ring cells away.
    if (found.size() >= k) {
      std::nth_element(found.begin(), found.begin() + static_cast<long>(k - 1), found.end());
      if (std::sqrt(found[k - 1].first) <= static_cast<double>(ring) * cell_) break;
    }
  }
  std::sort(found.begin(), found.end());
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < std::min(k, found.size()); ++i) out.push_back(found[i].second);
  return out;
}

double PointNeighbours::mean_spacing() const {
  const std::size_t n = points_.size(), step = std::max<std::size_t>(1, n / 2000);
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; i += step) {
    const std::vector<std::size_t> near = nearest(points_[i], 2);
    if (near.size() < 2) continue;
    const std::size_t j = near[0] == i ? near[1] : near[0];
    sum += std::hypot(points_[j][0] - points_[i][0], points_[j][1] - points_[i][1], points_[j][2] - points_[i][2]);
    ++count;
  }
  return count ? sum / static_cast<double>(count) : 1.0;
}

std::vector<Vec3> PointNeighbours::empty_floor(const Bounds3& box, double radius, double floor) const {
  std::vector<Vec3> out;
  const double ex = box.hi[0] - box.lo[0], ey = box.hi[1] - box.lo[1];
  const double step = std::max({radius, ex / 64, ey / 64, 1e-12});
  // A 2D neighbour test: the scan's points flattened to x-y.
  std::vector<Vec3> flat;
  for (const Vec3& p : points_) flat.push_back({p[0], p[1], 0});
  const PointNeighbours plane(flat);
  for (double y = box.lo[1] + step / 2; y < box.hi[1]; y += step)
    for (double x = box.lo[0] + step / 2; x < box.hi[0]; x += step) {
      const std::vector<std::size_t> near = plane.nearest({x, y, 0}, 1);
      if (near.empty() || std::hypot(flat[near[0]][0] - x, flat[near[0]][1] - y) > radius)
        out.push_back({x, y, floor});
    }
  return out;
}

}  // namespace csgfit::features_detail
