// Surface patches of a point set with normals: planes, spheres, cylinders, cones and tori found
// by CGAL's efficient RANSAC (Schnabel et al.), each with its fitted parameters and its points.
// One detector for every input that has a surface: range images, point clouds, mesh samples.
#pragma once

#include <atomic>
#include <cstdint>
#include <string_view>
#include <vector>

#include "csgfit/model/quaternion.h"

namespace csgfit {

enum class SurfaceKind { Plane, Sphere, Cylinder, Cone, Torus };

std::string_view to_string(SurfaceKind kind);

/// One detected surface and the points it explains.
struct SurfacePatch {
  SurfaceKind kind = SurfaceKind::Plane;
  /// Plane: a unit normal and a point on it (the centroid of its points).
  /// Sphere: the centre. Cylinder / torus: a point on the axis and the unit axis. Cone: the
  /// apex and the unit axis pointing into the cone.
  Vec3 point{0, 0, 0};
  Vec3 axis{0, 0, 1};
  double radius = 0;        ///< sphere, cylinder: radius; torus: major radius
  double minor_radius = 0;  ///< torus
  double angle = 0;         ///< cone: half-angle in radians
  std::vector<int> points;  ///< indices into the detector's input
  /// Whether the surface bulges towards the points' normals (the solid behind it is convex
  /// there: seed 002's positive primitive) rather than hollows (concave: a negative one).
  /// Always true for planes.
  bool convex = true;
  double rms = 0;           ///< root-mean-square distance of its points to the surface
};

/// The diagonal of the points' bounding box in their principal axes: the part's size, the
/// same however the part is turned (an axis-aligned box would not be), so that every tolerance
/// relative to it, and with them the fit, does not depend on the scanner's frame.
double part_diagonal(const std::vector<Vec3>& points);

/// Detector settings; zero means relative to part_diagonal of the points.
struct SurfaceDetectOptions {
  double epsilon = 0;         ///< max point-surface distance (default 0.4 % of the diagonal)
  double cluster_epsilon = 0; ///< max gap inside one patch (default 1.5 % of the diagonal)
  double normal_threshold = 0.95;  ///< min |cos| between a point's normal and the surface's
  int min_points = 0;         ///< smallest patch (default max(30, 0.2 % of the points))
  double probability = 0.01;  ///< RANSAC's chance of missing the largest shape
  bool planes = true, spheres = true, cylinders = true, cones = true, tori = true;
};

/// Detects the patches of `points` (with one unit normal each, pointing out of the part).
/// Deterministic for a given `seed`. Each point belongs to at most one patch; patches are in
/// the order found (largest first, as RANSAC extracts them), parameters refined by least
/// squares on the patch's points. When `cancel` turns true the detection stops with the
/// patches found so far, once it has one (about a second at most on a range image).
std::vector<SurfacePatch> detect_surfaces(const std::vector<Vec3>& points,
                                          const std::vector<Vec3>& normals,
                                          const SurfaceDetectOptions& options,
                                          std::uint64_t seed = 1,
                                          const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
