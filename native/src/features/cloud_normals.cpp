#include "features/cloud_normals.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>
#include <CGAL/remove_outliers.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>
#include <vector>

namespace csgfit::features_detail {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
// The original index travels with each point: CGAL partitions the range as it goes.
using Row = std::tuple<Point, Vector, std::size_t>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, Row>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, Row>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Turns the normals mst_orient_normals could not reach away from the centroid of all points:
// a separate piece of the cloud, which is outward for a piece of a convex-ish part.
void orient_away_from(const Point& centroid, std::vector<Row>::iterator begin,
                      std::vector<Row>::iterator end) {
  for (auto it = begin; it != end; ++it) {
    Vector& n = std::get<1>(*it);
    if ((std::get<0>(*it) - centroid) * n < 0) n = -n;
  }
}

}  // namespace

std::vector<Vec3> cloud_normals(const std::vector<Vec3>& points, int k, double outlier_spacing) {
  std::vector<Vec3> normals(points.size(), Vec3{kNaN, kNaN, kNaN});
  if (points.size() < 4 || k < 3) return normals;
  const unsigned kk = static_cast<unsigned>(std::min<std::size_t>(static_cast<std::size_t>(k),
                                                                  points.size() - 1));
  std::vector<Row> rows;
  rows.reserve(points.size());
  double sx = 0, sy = 0, sz = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    rows.emplace_back(Point(p[0], p[1], p[2]), Vector(0, 0, 0), i);
    sx += p[0], sy += p[1], sz += p[2];
  }
  const double n = static_cast<double>(points.size());
  const Point centroid(sx / n, sy / n, sz / n);
  const auto params = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());

  const double spacing =
      CGAL::compute_average_spacing<CGAL::Sequential_tag>(rows, kk, params);
  const auto kept_end = CGAL::remove_outliers<CGAL::Sequential_tag>(
      rows, kk, params.threshold_percent(100).threshold_distance(outlier_spacing * spacing));
  rows.erase(kept_end, rows.end());
  if (rows.size() < 4) return normals;
  const unsigned kept_k = static_cast<unsigned>(std::min<std::size_t>(kk, rows.size() - 1));

  CGAL::pca_estimate_normals<CGAL::Sequential_tag>(rows, kept_k, params);
  const auto oriented_end = CGAL::mst_orient_normals(rows, kept_k, params);
  orient_away_from(centroid, oriented_end, rows.end());
  for (const Row& r : rows) {
    const Vector& v = std::get<1>(r);
    const double len = std::sqrt(v.squared_length());
    if (!(len > 0) || !std::isfinite(len)) continue;
    normals[std::get<2>(r)] = {v.x() / len, v.y() / len, v.z() / len};
  }
  return normals;
}

}  // namespace csgfit::features_detail
