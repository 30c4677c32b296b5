#include "patch_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

Vec3 radial(const SurfacePatch& s, const Vec3& p) {
  return normalized(reject(sub(p, s.point), s.axis));
}

// The centroid and the scatter matrix of the patch's points (or normals).
Eigen::Matrix3d scatter(const std::vector<int>& idx, const std::vector<Vec3>& v, Vec3& mean) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int i : idx) m += view(v[i]);
  m /= static_cast<double>(idx.size());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (int i : idx) {
    const Eigen::Vector3d d = view(v[i]) - m;
    c += d * d.transpose();
  }
  mean = to_vec3(m);
  return c;
}

Vec3 least_variance_direction(const Eigen::Matrix3d& c) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c);
  return to_vec3(eig.eigenvectors().col(0));  // eigenvalues ascending
}

// RANSAC's plane normal has either sign: the points' own normals say which side is out.
void polish_plane(SurfacePatch& s, const std::vector<Vec3>& points,
                  const std::vector<Vec3>& normals) {
  Vec3 centroid;
  const Vec3 n = least_variance_direction(scatter(s.points, points, centroid));
  double agree = 0;
  for (int i : s.points) agree += dot(normals[i], n);
  s.point = centroid;
  s.axis = agree < 0 ? scale(n, -1) : n;
}

// Algebraic sphere |p|^2 + D.p + G = 0 by linear least squares (Eigen's QR), then the centre
// and radius it implies.
void polish_sphere(SurfacePatch& s, const std::vector<Vec3>& points) {
  Eigen::MatrixXd a(s.points.size(), 4);
  Eigen::VectorXd b(s.points.size());
  for (std::size_t r = 0; r < s.points.size(); ++r) {
    const Vec3& p = points[s.points[r]];
    a.row(static_cast<Eigen::Index>(r)) << p[0], p[1], p[2], 1;
    b(static_cast<Eigen::Index>(r)) = -squared(p);
  }
  const Eigen::Vector4d x = a.colPivHouseholderQr().solve(b);
  const Vec3 c{-x(0) / 2, -x(1) / 2, -x(2) / 2};
  const double r2 = squared(c) - x(3);
  if (!(r2 > 0) || !std::isfinite(r2)) return;
  s.point = c;
  s.radius = std::sqrt(r2);
}

// The algebraic (Kasa) circle is biased towards a smaller radius on a short arc, which is what
// a range image shows of a large cut: Gauss-Newton on the geometric distances |q - c| - r
// removes the bias. Rows of `a` are (x, y, 1) of the points across the axis.
void geometric_circle(const Eigen::MatrixXd& a, double& cu, double& cw, double& radius) {
  for (int iteration = 0; iteration < 10; ++iteration) {
    Eigen::MatrixXd j(a.rows(), 3);
    Eigen::VectorXd residual(a.rows());
    for (Eigen::Index r = 0; r < a.rows(); ++r) {
      const double dx = a(r, 0) - cu, dy = a(r, 1) - cw, d = std::hypot(dx, dy);
      if (d < 1e-12) return;
      j.row(r) << -dx / d, -dy / d, -1;
      residual(r) = d - radius;
    }
    const Eigen::Vector3d step = j.colPivHouseholderQr().solve(-residual);
    if (!step.allFinite()) return;
    cu += step(0), cw += step(1), radius += step(2);
    if (step.norm() < 1e-12 * (1 + radius)) break;
  }
}

// A cylinder's normals are perpendicular to its axis: the axis is their direction of least
// variance about the origin. The circle is then fitted in the plane across the axis.
void polish_cylinder(SurfacePatch& s, const std::vector<Vec3>& points,
                     const std::vector<Vec3>* normals) {
  if (normals) {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    for (int i : s.points) c += view((*normals)[i]) * view((*normals)[i]).transpose();
    const Vec3 axis = least_variance_direction(c);
    if (std::abs(dot(axis, s.axis)) > 0.9) s.axis = dot(axis, s.axis) < 0 ? scale(axis, -1) : axis;
  }
  std::vector<Vec3> selected;
  selected.reserve(s.points.size());
  for (int i : s.points) selected.push_back(points[i]);
  const AxisCircle c = fit_axis_circle(selected, s.point, s.axis);
  if (!c.ok) return;
  s.point = c.centre;
  s.radius = c.radius;
}

}  // namespace

AxisCircle fit_axis_circle(const std::vector<Vec3>& points, const Vec3& origin, const Vec3& axis) {
  AxisCircle out;
  const Vec3 u = normalized(reject(std::abs(axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, axis));
  const Vec3 w = cross(axis, u);
  Eigen::MatrixXd a(points.size(), 3);
  Eigen::VectorXd b(points.size());
  for (std::size_t r = 0; r < points.size(); ++r) {
    const Vec3 d = sub(points[r], origin);
    const double x = dot(d, u), y = dot(d, w);
    a.row(static_cast<Eigen::Index>(r)) << x, y, 1;
    b(static_cast<Eigen::Index>(r)) = -(x * x + y * y);
  }
  const Eigen::Vector3d x = a.colPivHouseholderQr().solve(b);
  double cu = -x(0) / 2, cw = -x(1) / 2;
  const double r2 = cu * cu + cw * cw - x(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return out;
  double radius = std::sqrt(r2);
  geometric_circle(a, cu, cw, radius);
  out.ok = std::isfinite(radius) && radius > 0;
  out.centre = add(origin, add(scale(u, cu), scale(w, cw)));
  out.radius = radius;
  for (const Vec3& p : points)
    out.max_error = std::max(out.max_error, std::abs(norm(reject(sub(p, out.centre), axis)) - radius));
  return out;
}

double surface_distance(const SurfacePatch& s, const Vec3& p) {
  const Vec3 d = sub(p, s.point);
  switch (s.kind) {
    case SurfaceKind::Plane: return dot(d, s.axis);
    case SurfaceKind::Sphere: return norm(d) - s.radius;
    case SurfaceKind::Cylinder: return norm(reject(d, s.axis)) - s.radius;
    case SurfaceKind::Cone: {
      const double h = dot(d, s.axis), rho = norm(reject(d, s.axis));
      return rho * std::cos(s.angle) - h * std::sin(s.angle);
    }
    case SurfaceKind::Torus: {
      const double h = dot(d, s.axis), rho = norm(reject(d, s.axis)) - s.radius;
      return std::sqrt(rho * rho + h * h) - s.minor_radius;
    }
  }
  return 0;
}

Vec3 surface_normal(const SurfacePatch& s, const Vec3& p) {
  switch (s.kind) {
    case SurfaceKind::Plane: return s.axis;
    case SurfaceKind::Sphere: return normalized(sub(p, s.point));
    case SurfaceKind::Cylinder: return radial(s, p);
    case SurfaceKind::Cone:
      return normalized(sub(scale(radial(s, p), std::cos(s.angle)),
                            scale(s.axis, std::sin(s.angle))));
    case SurfaceKind::Torus: {
      const Vec3 core = add(s.point, scale(radial(s, p), s.radius));
      return normalized(sub(p, core));
    }
  }
  return s.axis;
}

void polish_patch(SurfacePatch& s, const std::vector<Vec3>& points,
                  const std::vector<Vec3>& normals) {
  if (s.points.size() < 8) return;
  if (s.kind == SurfaceKind::Plane) polish_plane(s, points, normals);
  if (s.kind == SurfaceKind::Sphere) polish_sphere(s, points);
  if (s.kind == SurfaceKind::Cylinder) polish_cylinder(s, points, &normals);
}

bool is_convex(const SurfacePatch& s, const std::vector<Vec3>& points,
               const std::vector<Vec3>& normals) {
  if (s.kind == SurfaceKind::Plane) return true;
  std::size_t agree = 0;
  for (int i : s.points) agree += dot(normals[i], surface_normal(s, points[i])) > 0;
  return 2 * agree >= s.points.size();
}

double patch_rms(const SurfacePatch& s, const std::vector<Vec3>& points) {
  if (s.points.empty()) return 0;
  double sum = 0;
  for (int i : s.points) sum += std::pow(surface_distance(s, points[i]), 2);
  return std::sqrt(sum / static_cast<double>(s.points.size()));
}

}  // namespace csgfit
