// Internal: the few affine operations on OpenSCAD's 4 x 4 matrices the program reader needs.
#pragma once

#include <cmath>

#include "csgfit/io/openscad_program.h"

namespace csgfit::scadm {

inline Matrix4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

inline Matrix4 multiply(const Matrix4& a, const Matrix4& b) {
  Matrix4 c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[4 * i + j] += a[4 * i + k] * b[4 * k + j];
  return c;
}

inline double det3(const Matrix4& m) {
  return m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
         m[2] * (m[4] * m[9] - m[5] * m[8]);
}

/// The inverse of an affine matrix (last row 0 0 0 1); det3 must not be 0.
inline Matrix4 inverse_affine(const Matrix4& m) {
  const double d = det3(m);
  Matrix4 r = identity();
  r[0] = (m[5] * m[10] - m[6] * m[9]) / d;
  r[1] = (m[2] * m[9] - m[1] * m[10]) / d;
  r[2] = (m[1] * m[6] - m[2] * m[5]) / d;
  r[4] = (m[6] * m[8] - m[4] * m[10]) / d;
  r[5] = (m[0] * m[10] - m[2] * m[8]) / d;
  r[6] = (m[2] * m[4] - m[0] * m[6]) / d;
  r[8] = (m[4] * m[9] - m[5] * m[8]) / d;
  r[9] = (m[1] * m[8] - m[0] * m[9]) / d;
  r[10] = (m[0] * m[5] - m[1] * m[4]) / d;
  for (int i = 0; i < 3; ++i) r[4 * i + 3] = -(r[4 * i] * m[3] + r[4 * i + 1] * m[7] + r[4 * i + 2] * m[11]);
  return r;
}

inline std::array<double, 3> apply(const Matrix4& m, double x, double y, double z) {
  return {m[0] * x + m[1] * y + m[2] * z + m[3], m[4] * x + m[5] * y + m[6] * z + m[7],
          m[8] * x + m[9] * y + m[10] * z + m[11]};
}

inline bool is_identity(const Matrix4& m, double tol = 1e-12) {
  const Matrix4 id = identity();
  for (int i = 0; i < 16; ++i)
    if (std::abs(m[i] - id[i]) > tol) return false;
  return true;
}

}  // namespace csgfit::scadm
