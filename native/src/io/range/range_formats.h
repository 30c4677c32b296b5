// The range formats read_range dispatches to by extension. Each works on the whole file `d` in
// memory, checks each declared size against the limits before it allocates anything for it,
// and refuses a file cut short with one line (InputError naming `path`).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "csgfit/io/range_read.h"
#include "csgfit/model/range_scan.h"

namespace csgfit::io_detail {

/// Where the sidecar of `image_path` is: the same name with the extension .json.
std::string sidecar_path(const std::string& image_path);

/// A camera and what its sidecar says besides: the PNG value of "no return".
struct SidecarCamera {
  RangeCamera camera;
  double no_return = 0;
};

/// read_range_camera, with the sidecar's no_return value.
std::optional<SidecarCamera> read_sidecar_camera(const std::string& image_path, int width,
                                                 int height, const RangeIntrinsics& intrinsics);

/// The camera of a depth image, or the one line that says what is missing.
SidecarCamera depth_camera(const std::string& image_path, int width, int height,
                           const RangeIntrinsics& intrinsics);

/// Back-projects a depth map (row-major, `camera.width` x `camera.height`; NaN, infinite and
/// non-positive depths are no return) into a scan in model coordinates, without normals.
RangeScan scan_from_depth(const std::string& path, const RangeCamera& camera,
                          const std::vector<double>& depth);

/// A 16-bit grey PNG depth image with its sidecar (or intrinsics).
RangeScan read_depth_png(const std::string& path, const std::string& d,
                         const RangeReadOptions& options);

/// A .npy: an H x W float depth map with its sidecar, or an H x W x 3 organised cloud in model
/// coordinates; for the cloud, *view_direction gets the view of a sidecar of its size next to
/// it (NAME.json, or NAME_ortho.json for NAME_xyz.npy), to turn its normals by.
RangeScan read_npy_range(const std::string& path, const std::string& d,
                         const RangeReadOptions& options, std::optional<Vec3>* view_direction);

/// Text "x y z" or "x y z nx ny nz" per line, # comments.
RangeScan read_xyz_points(const std::string& path, const std::string& d,
                          const RangeReadOptions& options);

/// PLY vertices x y z (nx ny nz): organised when the header gives width and height that
/// multiply to the vertex count.
RangeScan read_ply_points(const std::string& path, const std::string& d,
                          const RangeReadOptions& options);

/// Refuses a scan without one point (every pixel without a return).
void check_has_returns(const RangeScan& scan);

}  // namespace csgfit::io_detail
