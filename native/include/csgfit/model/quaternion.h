// Rotations and the small vector types of 3D: unit quaternions, 3-vectors and 3x3 matrices.
#pragma once

#include <array>

namespace csgfit {

using Vec3 = std::array<double, 3>;
/// Row-major 3x3 matrix; m[i][j] is row i, column j.
using Mat3 = std::array<std::array<double, 3>, 3>;

/// A rotation as a unit quaternion (w, x, y, z). It maps the primitive's local frame into model
/// coordinates: model = centre + R * local, so the columns of matrix() are the local axes.
/// A quaternion is stored (not Euler angles) because small rotations compose without gimbal
/// lock in the optimiser; euler_deg() gives the angles OpenSCAD's rotate() wants.
struct Quaternion {
  double w = 1, x = 0, y = 0, z = 0;

  /// Rotation by `degrees` about the axis (ax, ay, az) (need not be unit; zero = identity).
  static Quaternion from_axis_angle(double ax, double ay, double az, double degrees);
  /// OpenSCAD's rotate([a, b, c]): first about x by a, then about y by b, then about z by c
  /// (degrees, right-handed): R = Rz(c) * Ry(b) * Rx(a).
  static Quaternion from_euler_deg(double a, double b, double c);
  /// Angles {a, b, c} such that from_euler_deg(a, b, c) is this rotation: b in [-90, 90],
  /// a and c in (-180, 180]; at b = +-90 (gimbal lock) a is 0.
  Vec3 euler_deg() const;
  /// The rotation matrix (local -> model).
  Mat3 matrix() const;
  /// Composition: (p * q) rotates by q first, then by p.
  Quaternion operator*(const Quaternion& o) const;
  /// Rescales to unit length with w >= 0 (q and -q are the same rotation); a zero or
  /// non-finite quaternion becomes the identity.
  void normalize();
  bool is_identity(double tolerance = 1e-12) const;
  bool operator==(const Quaternion& o) const {
    return w == o.w && x == o.x && y == o.y && z == o.z;
  }
};

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: values descending,
/// vectors as the matching columns of a right-handed orthonormal matrix.
void symmetric_eigen3(const Mat3& a, Vec3& values, Mat3& vectors);

/// The unit quaternion of a rotation matrix (columns = the rotated axes; det must be +1).
Quaternion quaternion_from_matrix(const Mat3& m);

}  // namespace csgfit
