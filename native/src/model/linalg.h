// Internal to the solver: the small linear algebra of 3D on Eigen, over the API's own value
// types. Vec3 and Mat3 (row-major) stay std::arrays, so that the public headers, the JSON and
// the Python bindings need no Eigen; Eigen maps them in place.
//
// Eigen sums a 3-term dot product as a0 + (a1 + a2) and solves systems in its own order, so
// code whose rounding steers a search (the moment axes, the surface fit's normal equations,
// the mesh's rotation into the fitting frame) keeps its own loops until a change that may move
// the fixed-seed results (scripts/golden.py) takes them over.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "csgfit/model/quaternion.h"

namespace csgfit::linalg {

static_assert(sizeof(Mat3) == 9 * sizeof(double), "Mat3 must be nine contiguous doubles");

using ConstVector = Eigen::Map<const Eigen::Vector3d>;
using RowMajor3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using ConstMatrix = Eigen::Map<const RowMajor3d>;

inline ConstVector view(const Vec3& v) { return ConstVector(v.data()); }
inline ConstMatrix view(const Mat3& m) { return ConstMatrix(m[0].data()); }
inline Vec3 to_vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline double dot(const Vec3& a, const Vec3& b) { return view(a).dot(view(b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) { return to_vec3(view(a).cross(view(b))); }
inline Vec3 column(const Mat3& m, int c) { return to_vec3(view(m).col(c)); }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double squared(const Vec3& a) { return dot(a, a); }
inline double norm(const Vec3& a) { return view(a).norm(); }
/// a / |a|, or {0, 0, 0} for a zero vector.
inline Vec3 normalized(const Vec3& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1 / n) : Vec3{0, 0, 0};
}
/// The part of a perpendicular to the unit vector d.
inline Vec3 reject(const Vec3& a, const Vec3& d) { return sub(a, scale(d, dot(a, d))); }

}  // namespace csgfit::linalg
