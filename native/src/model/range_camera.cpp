#include <cmath>
#include <cstdio>
#include <string>

#include "csgfit/error.h"
#include "csgfit/model/range_scan.h"
#include "model/linalg.h"

namespace csgfit {

namespace {

// Sidecars are written with nine decimals, so a rotation that is orthonormal to 1e-4 is the
// writer's rounding, and anything further off is a scale, a shear or a mirror in the file.
constexpr double kRigidTolerance = 1e-4;
// No sensor has more pixels a side than this; a larger width is a corrupt sidecar.
constexpr int kMaxSide = 1 << 20;

using Matrix4 = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;

Eigen::Map<const Matrix4> pose(const RangeCamera& c) {
  return Eigen::Map<const Matrix4>(c.camera_to_world.data());
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

[[noreturn]] void bad_camera(const std::string& what) {
  throw InputError("bad range camera: " + what);
}

void check_positive(double v, const char* name) {
  if (!std::isfinite(v)) bad_camera(std::string(name) + " is not finite");
  if (!(v > 0)) bad_camera(std::string(name) + " must be positive, not " + number_text(v));
}

void check_pose(const RangeCamera& c) {
  for (double v : c.camera_to_world) {
    if (!std::isfinite(v)) bad_camera("camera_to_world holds a value that is not finite");
  }
  const auto m = pose(c);
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1) {
    bad_camera("the last row of camera_to_world must be 0 0 0 1 (a rigid transform)");
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kRigidTolerance)) {
    bad_camera("the rotation of camera_to_world is not orthonormal (R^T R is off the identity by " +
               number_text(off) + "): it scales, shears or is singular");
  }
  const double det = r.determinant();
  if (!(std::abs(det - 1) <= kRigidTolerance * 3)) {
    bad_camera("the rotation of camera_to_world has determinant " + number_text(det) +
               ", not +1 (a mirror)");
  }
}

}  // namespace

Vec3 RangeCamera::camera_point(double u, double v, double depth) const {
  if (projection == Projection::Orthographic) {
    return {(u + 0.5 - cx) * pixel_size, (v + 0.5 - cy) * pixel_size, depth};
  }
  return {(u + 0.5 - cx) / fx * depth, (v + 0.5 - cy) / fy * depth, depth};
}

Vec3 RangeCamera::world_point(double u, double v, double depth) const {
  const Vec3 c = camera_point(u, v, depth);
  const Eigen::Vector4d w = pose(*this) * Eigen::Vector4d(c[0], c[1], c[2], 1);
  return {w.x(), w.y(), w.z()};
}

Vec3 RangeCamera::ray_origin(double u, double v) const { return world_point(u, v, 0); }

Vec3 RangeCamera::ray_direction(double u, double v) const {
  if (projection == Projection::Orthographic) return view_direction();
  const Eigen::Vector3d d(camera_point(u, v, 1).data());
  return linalg::to_vec3(pose(*this).topLeftCorner<3, 3>() * d.normalized());
}

Vec3 RangeCamera::view_direction() const {
  return linalg::to_vec3(pose(*this).block<3, 1>(0, 2).normalized());
}

Vec3 RangeCamera::project(const Vec3& world) const {
  const auto m = pose(*this);
  // The inverse, not R^T: a sidecar's nine decimals leave R orthonormal only to 1e-9, and
  // world_point(project(p)) should give p back to rounding.
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const Eigen::Vector3d c = r.inverse() * (linalg::view(world) - m.block<3, 1>(0, 3));
  const double depth = c.z();
  if (projection == Projection::Orthographic) {
    return {c.x() / pixel_size + cx - 0.5, c.y() / pixel_size + cy - 0.5, depth};
  }
  if (!(depth > 0)) return {0, 0, depth};
  return {c.x() / depth * fx + cx - 0.5, c.y() / depth * fy + cy - 0.5, depth};
}

void RangeCamera::validate() const {
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide) {
    bad_camera("the image size " + std::to_string(width) + " x " + std::to_string(height) +
               " is not a sensor's (each side 1 to " + std::to_string(kMaxSide) + " pixels)");
  }
  if (projection == Projection::Orthographic) {
    check_positive(pixel_size, "pixel_size");
  } else {
    check_positive(fx, "fx");
    check_positive(fy, "fy");
  }
  if (!std::isfinite(cx) || !std::isfinite(cy)) bad_camera("cx or cy is not finite");
  check_positive(depth_unit, "depth_unit");
  check_pose(*this);
}

}  // namespace csgfit
