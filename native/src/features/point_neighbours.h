// Internal: nearest neighbours of a point cloud on a uniform grid of cells (the fitness and the
// curvature types need thousands of small queries; CGAL's trees stay in cloud_normals.cpp).
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

#include "csgfit/model/primitive3d.h"

namespace csgfit::features_detail {

class PointNeighbours {
 public:
  /// Cells of about two points each; the points are referenced, not copied.
  explicit PointNeighbours(const std::vector<Vec3>& points);
  /// Indices of the k points nearest to q (fewer when the cloud is smaller), nearest first.
  std::vector<std::size_t> nearest(const Vec3& q, std::size_t k) const;
  /// Mean distance from a point to its nearest other point (over up to 2000 points).
  double mean_spacing() const;
  /// Points at height `floor` on a grid of step `radius` over the box's x-y extent (at most
  /// 64 x 64) where no point's x-y lies within `radius`.
  std::vector<Vec3> empty_floor(const Bounds3& box, double radius, double floor) const;

 private:
  long long key(long long i, long long j, long long k) const;
  void cell_of(const Vec3& p, long long c[3]) const;
  const std::vector<Vec3>& points_;
  Bounds3 box_;
  double cell_ = 1;
  long long n_[3] = {1, 1, 1};
  std::unordered_map<long long, std::vector<std::size_t>> cells_;
};

}  // namespace csgfit::features_detail
