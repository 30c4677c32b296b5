// Patch adjacency on a uniform grid of cells of the contact radius: two patches touch when
// enough of their points are that close. Point-wise rather than through the image so that
// merged views and unorganised clouds are treated alike.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "csgfit/seed/range_primitives.h"
#include "model/linalg.h"

namespace csgfit {

namespace {

using Cell = long long;

Cell cell_key(long long x, long long y, long long z) {
  return (x * 73856093LL) ^ (y * 19349663LL) ^ (z * 83492791LL);
}

}  // namespace

std::vector<std::vector<int>> patch_adjacency(const std::vector<SurfacePatch>& patches,
                                              const std::vector<Vec3>& points, double radius) {
  const std::size_t n = patches.size();
  std::vector<int> owner(points.size(), -1);
  for (std::size_t k = 0; k < n; ++k)
    for (int i : patches[k].points) owner[i] = static_cast<int>(k);
  std::unordered_map<Cell, std::vector<int>> grid;
  const auto coord = [&](double v) { return static_cast<long long>(std::floor(v / radius)); };
  for (std::size_t i = 0; i < points.size(); ++i)
    if (owner[i] >= 0)
      grid[cell_key(coord(points[i][0]), coord(points[i][1]), coord(points[i][2]))].push_back(
          static_cast<int>(i));

  // Contacts are counted once per point and neighbouring patch, so a long shared edge and a
  // single stray point are told apart.
  std::vector<std::vector<int>> contacts(n, std::vector<int>(n, 0));
  const double r2 = radius * radius;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (owner[i] < 0) continue;
    std::vector<char> seen(n, 0);
    const long long cx = coord(points[i][0]), cy = coord(points[i][1]), cz = coord(points[i][2]);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(cell_key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            const int other = owner[j];
            if (other == owner[i] || seen[other]) continue;
            if (linalg::squared(linalg::sub(points[i], points[j])) > r2) continue;
            seen[other] = 1;
            ++contacts[owner[i]][other];
          }
        }
  }
  std::vector<std::vector<int>> adjacent(n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b)
      if (a != b && std::min(contacts[a][b], contacts[b][a]) >= 3)
        adjacent[a].push_back(static_cast<int>(b));
  return adjacent;
}

}  // namespace csgfit
