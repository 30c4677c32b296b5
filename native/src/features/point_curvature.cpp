#include "csgfit/features/point_curvature.h"

#include <cmath>

#include "features/point_neighbours.h"

namespace csgfit {

CurvatureType classify_curvature(double k, double spread, double size) {
  if (spread > 0.25) return CurvatureType::Other;
  if (std::fabs(k) * size < 2) return CurvatureType::Flat;
  return k > 0 ? CurvatureType::Convex : CurvatureType::Concave;
}

std::vector<CurvatureType> curvature_types(const std::vector<Vec3>& points,
                                           const std::vector<Vec3>& normals, double size) {
  const features_detail::PointNeighbours grid(points);
  std::vector<CurvatureType> out(points.size(), CurvatureType::Other);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::vector<std::size_t> near = grid.nearest(points[i], 13);
    double sum = 0;
    int count = 0, up = 0, down = 0;
    for (std::size_t j : near) {
      if (j == i) continue;
      double dot = 0, len2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double dp = points[j][a] - points[i][a];
        dot += (normals[j][a] - normals[i][a]) * dp;
        len2 += dp * dp;
      }
      if (!(len2 > 0)) continue;
      const double k = dot / len2;
      sum += k, ++count;
      if (k * size > 2) ++up;
      if (k * size < -2) ++down;
    }
    if (count == 0) continue;
    const double k = sum / count;
    const double spread = static_cast<double>(k > 0 ? down : up) / count;
    out[i] = classify_curvature(k, spread, size);
  }
  return out;
}

}  // namespace csgfit
