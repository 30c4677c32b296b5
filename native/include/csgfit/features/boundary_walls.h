// Straight edges of a bitmap's shape: the walls a designer's rectangles leave on its boundary.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "csgfit/model/bitmap.h"

namespace csgfit {

/// One straight edge: the shape lies on the side p . n <= offset of the line, n its outward
/// normal (solver frame, pixel units).
struct BoundaryWall {
  double offset = 0;
  std::size_t support = 0;  ///< boundary pixels on it
};

/// The walls of one orientation: `angle` in [0, 90) degrees, and the walls whose outward normal
/// points at angle + 90 k for k = 0..3, strongest first.
struct WallFamily {
  double angle = 0;
  std::array<std::vector<BoundaryWall>, 4> walls;
};

/// The dominant edge orientations of `mask` (modulo 90 degrees, so that a rectangle's four
/// sides are one family) and their walls. Normals come from a Gaussian-weighted neighbourhood of
/// each boundary pixel; a wall's offset is corrected for the half pixel its boundary pixels lie
/// inside the edge. At most `max_families`, strongest first.
std::vector<WallFamily> boundary_walls(const Bitmap& mask, std::size_t max_families = 4);

}  // namespace csgfit
