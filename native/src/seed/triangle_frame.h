// Internal to seed/: a triangle given by its vertices, dimensioned the way the 2D Triangle and
// the 3D prism are (primitive2d.h): the longest edge is the base, which is how a designer
// would dimension it.
#pragma once

#include <cmath>
#include <utility>

namespace csgfit {

/// The centre of the triangle's local frame, the base width w and height h, the base's
/// direction (radians, counter-clockwise) and the apex offset along the base in units of w/2.
struct TriangleFrame {
  double cx, cy, w, h, angle, apex;
};

inline TriangleFrame triangle_frame(const double v[3][2]) {
  int base = 0;
  double best = -1;
  for (int i = 0; i < 3; ++i) {
    const double dx = v[(i + 1) % 3][0] - v[i][0], dy = v[(i + 1) % 3][1] - v[i][1];
    const double len = dx * dx + dy * dy;
    if (len > best) best = len, base = i;
  }
  const double* a = v[base];
  const double* b = v[(base + 1) % 3];
  const double* c = v[(base + 2) % 3];
  double ux = b[0] - a[0], uy = b[1] - a[1];
  const double w = std::sqrt(ux * ux + uy * uy);
  ux /= w, uy /= w;
  double nx = -uy, ny = ux;
  double hgt = (c[0] - a[0]) * nx + (c[1] - a[1]) * ny;
  if (hgt < 0) {  // apex on the other side: walk the base the other way round
    ux = -ux, uy = -uy, nx = -nx, ny = -ny, hgt = -hgt;
    std::swap(a, b);
  }
  const double mx = 0.5 * (a[0] + b[0]), my = 0.5 * (a[1] + b[1]);
  const double along = (c[0] - mx) * ux + (c[1] - my) * uy;
  return {mx + nx * hgt / 2, my + ny * hgt / 2, w, hgt, std::atan2(uy, ux), along / (w / 2)};
}

}  // namespace csgfit
