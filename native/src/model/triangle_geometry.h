// Vector arithmetic on mesh vertices, shared by the mesh readers (degenerate triangles), the
// topology checks (area, signed volume) and the voxeliser.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

namespace csgfit::geometry {

using Point = std::array<double, 3>;

/// A hash of a position's exact bits (pass -0 as +0 first): welding and canonical ids use it.
inline std::uint64_t position_hash(const Point& p) {
  std::uint64_t h = 1469598103934665603ULL;
  for (double c : p) {
    std::uint64_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    h = (h ^ bits) * 1099511628211ULL;
    h ^= h >> 29;
  }
  return h;
}

inline Point minus(const Point& b, const Point& a) {
  return {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
}

inline Point cross(const Point& u, const Point& v) {
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

inline double dot(const Point& u, const Point& v) {
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

/// Six times the signed volume of the tetrahedron (o, a, b, c): positive when a, b, c run
/// counter-clockwise seen from the side away from o. Relative to o, so that a part far from
/// the origin loses no precision.
inline double six_signed_volume(const Point& o, const Point& a, const Point& b, const Point& c) {
  return dot(minus(a, o), cross(minus(b, o), minus(c, o)));
}

}  // namespace csgfit::geometry
