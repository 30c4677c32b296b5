// What a range sensor saw: the camera that turns a pixel and a depth into a point, and the
// points (with normals) of one view or of an unorganised cloud, in the part's own coordinates.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "csgfit/model/quaternion.h"

namespace csgfit {

enum class Projection { Orthographic, Pinhole };

/// A range camera as the sidecar of ../shared/benchmarks/range/README.md describes it. Camera
/// coordinates: x right, y down, z forward along the view. Pixel (u, v) is (column, row),
/// 0-based; its centre is (u + 0.5, v + 0.5).
struct RangeCamera {
  Projection projection = Projection::Orthographic;
  int width = 0, height = 0;
  double pixel_size = 0;        ///< orthographic: model units per pixel
  double fx = 0, fy = 0;        ///< pinhole: focal lengths in pixels
  double cx = 0, cy = 0;        ///< principal point in pixels
  double depth_unit = 1;        ///< a 16-bit PNG value times this is the depth
  /// Camera -> model coordinates, row-major 4 x 4, rigid (rotation + translation).
  std::array<double, 16> camera_to_world{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

  /// The point at `depth` along pixel (u, v)'s ray, in camera coordinates.
  Vec3 camera_point(double u, double v, double depth) const;
  /// The same in model coordinates.
  Vec3 world_point(double u, double v, double depth) const;
  /// Where pixel (u, v)'s ray starts (depth 0) and its unit direction, in model coordinates.
  Vec3 ray_origin(double u, double v) const;
  Vec3 ray_direction(double u, double v) const;
  /// The sensor's viewing direction (camera +z) in model coordinates.
  Vec3 view_direction() const;
  /// Model point -> (u, v, depth); depth <= 0 when the point is behind the camera.
  Vec3 project(const Vec3& world) const;
  /// Throws InputError (one line, naming what is wrong) for a non-rigid or non-finite
  /// camera_to_world, a non-positive pixel size, focal length or depth unit, a bad size.
  void validate() const;
};

/// The points of one range image (organised: each point knows its pixel) or of an unorganised
/// cloud, in model coordinates, with unit normals pointing out of the part (towards the sensor
/// that saw them). Points are kept in pixel order for an organised scan.
struct RangeScan {
  std::string source;                 ///< the file it came from (for messages)
  std::optional<RangeCamera> camera;  ///< the sensor, when known (depth images)
  int width = 0, height = 0;          ///< > 0 for an organised scan
  std::vector<Vec3> points;
  std::vector<Vec3> normals;          ///< one per point once estimated; empty before
  std::vector<int> pixel;             ///< organised: v * width + u of each point; else empty
  std::size_t dropped_no_return = 0;  ///< pixels without a return (0, NaN)
  std::size_t dropped_outliers = 0;   ///< returns dropped as outliers (isolated, or NaN normals)

  bool organised() const { return width > 0 && height > 0; }
};

}  // namespace csgfit
