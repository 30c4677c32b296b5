#include "csgfit/model/quaternion.h"

#include <algorithm>
#include <cmath>

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

double wrap_degrees(double a) {
  a = std::fmod(a, 360.0);
  if (a <= -180) a += 360;
  if (a > 180) a -= 360;
  return a;
}

}  // namespace

Quaternion Quaternion::from_axis_angle(double ax, double ay, double az, double degrees) {
  const double len = std::sqrt(ax * ax + ay * ay + az * az);
  if (!(len > 0)) return Quaternion{};
  const double half = 0.5 * degrees * kDegToRad;
  const double s = std::sin(half) / len;
  Quaternion q{std::cos(half), ax * s, ay * s, az * s};
  q.normalize();
  return q;
}

Quaternion Quaternion::from_euler_deg(double a, double b, double c) {
  Quaternion q = from_axis_angle(0, 0, 1, c) * from_axis_angle(0, 1, 0, b) *
                 from_axis_angle(1, 0, 0, a);
  q.normalize();
  return q;
}

Vec3 Quaternion::euler_deg() const {
  const Mat3 m = matrix();
  // R = Rz(c) Ry(b) Rx(a): m[2][0] = -sin b, m[2][1] = cos b sin a, m[2][2] = cos b cos a,
  // m[1][0] = sin c cos b, m[0][0] = cos c cos b.
  const double cb = std::hypot(m[0][0], m[1][0]);
  double a, b, c;
  b = std::atan2(-m[2][0], cb);
  if (cb > 1e-9) {
    a = std::atan2(m[2][1], m[2][2]);
    c = std::atan2(m[1][0], m[0][0]);
  } else {
    // Gimbal lock: only a - c (or a + c) is defined; put it all in c.
    a = 0;
    c = std::atan2(-m[0][1], m[1][1]);
  }
  return {wrap_degrees(a * kRadToDeg), b * kRadToDeg, wrap_degrees(c * kRadToDeg)};
}

Mat3 Quaternion::matrix() const {
  const double xx = x * x, yy = y * y, zz = z * z;
  const double xy = x * y, xz = x * z, yz = y * z;
  const double wx = w * x, wy = w * y, wz = w * z;
  return Mat3{{{1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy)},
               {2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx)},
               {2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)}}};
}

Quaternion Quaternion::operator*(const Quaternion& o) const {
  return Quaternion{w * o.w - x * o.x - y * o.y - z * o.z, w * o.x + x * o.w + y * o.z - z * o.y,
                    w * o.y - x * o.z + y * o.w + z * o.x, w * o.z + x * o.y - y * o.x + z * o.w};
}

void Quaternion::normalize() {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  if (!(n > 0) || !std::isfinite(n)) {
    *this = Quaternion{};
    return;
  }
  const double s = (w < 0 ? -1.0 : 1.0) / n;
  w *= s, x *= s, y *= s, z *= s;
}

bool Quaternion::is_identity(double tolerance) const {
  return std::fabs(x) <= tolerance && std::fabs(y) <= tolerance && std::fabs(z) <= tolerance;
}

void symmetric_eigen3(const Mat3& a_in, Vec3& values, Mat3& vectors) {
  double a[3][3];
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = 0.5 * (a_in[i][j] + a_in[j][i]);
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * std::max(diag, 1e-300)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        // Classic Jacobi rotation zeroing a[p][q] (Numerical Recipes' stable form).
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // columns p, q
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // rows p, q
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return a[x][x] > a[y][y]; });
  for (int c = 0; c < 3; ++c) {
    values[c] = a[order[c]][order[c]];
    for (int r = 0; r < 3; ++r) vectors[r][c] = v[r][order[c]];
  }
  // Right-handed: third axis = first x second.
  const double det = vectors[0][0] * (vectors[1][1] * vectors[2][2] - vectors[2][1] * vectors[1][2]) -
                     vectors[0][1] * (vectors[1][0] * vectors[2][2] - vectors[2][0] * vectors[1][2]) +
                     vectors[0][2] * (vectors[1][0] * vectors[2][1] - vectors[2][0] * vectors[1][1]);
  if (det < 0)
    for (int r = 0; r < 3; ++r) vectors[r][2] = -vectors[r][2];
}

Quaternion quaternion_from_matrix(const Mat3& m) {
  Quaternion q;
  const double tr = m[0][0] + m[1][1] + m[2][2];
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    q.w = 0.25 * s;
    q.x = (m[2][1] - m[1][2]) / s;
    q.y = (m[0][2] - m[2][0]) / s;
    q.z = (m[1][0] - m[0][1]) / s;
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2;
    q.w = (m[2][1] - m[1][2]) / s;
    q.x = 0.25 * s;
    q.y = (m[0][1] + m[1][0]) / s;
    q.z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] > m[2][2]) {
    const double s = std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2;
    q.w = (m[0][2] - m[2][0]) / s;
    q.x = (m[0][1] + m[1][0]) / s;
    q.y = 0.25 * s;
    q.z = (m[1][2] + m[2][1]) / s;
  } else {
    const double s = std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2;
    q.w = (m[1][0] - m[0][1]) / s;
    q.x = (m[0][2] + m[2][0]) / s;
    q.y = (m[1][2] + m[2][1]) / s;
    q.z = 0.25 * s;
  }
  q.normalize();
  return q;
}

}  // namespace csgfit
