// Reading range images and point clouds: depth maps (16-bit PNG, float .npy) with their JSON
// sidecar, organised clouds (.npy H x W x 3, PLY with width/height) and unorganised points
// (.xyz, .ply, with or without normals).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "csgfit/model/range_scan.h"

namespace csgfit {

/// Intrinsics given on the command line: each set field replaces the sidecar's, and with no
/// sidecar they must say enough to make a camera (pixel size, or fx and fy; cx, cy default to
/// the image centre; depth unit defaults to 1; camera_to_world to the identity).
struct RangeIntrinsics {
  std::optional<double> fx, fy, cx, cy, pixel_size, depth_unit;
};

struct RangeReadOptions {
  RangeIntrinsics intrinsics;
  long long max_pixels = 4096LL * 4096LL;  ///< larger images are refused (InputError names it)
  long long max_points = 20'000'000;       ///< larger clouds are refused
  /// Unorganised scan files (csgfit points): a NaN or infinite coordinate, or a normal of zero
  /// length, is an error naming the point rather than a missing return or an outlier.
  bool strict_points = false;
};

/// Reads one view or cloud by its extension (.png, .npy, .ply, .xyz), drops NaN / no-return
/// pixels and outliers (counted in the scan), and estimates normals where the file has none
/// (organised: from the image neighbourhood; unorganised: PCA of the k nearest neighbours,
/// oriented consistently, outwards). Throws InputError (one line, naming the file) for a missing
/// or unreadable file, a PNG without a sidecar or intrinsics, a bad sidecar, an 8-bit PNG given
/// as depth, an image over the limits, no returns.
RangeScan read_range(const std::string& path, const RangeReadOptions& options = {});

/// The sidecar next to `image_path` (same name, .json), checked by RangeCamera::validate, with
/// `intrinsics` applied over it; std::nullopt when there is no sidecar and the intrinsics do not
/// make a camera. Throws InputError for a sidecar that is not valid.
std::optional<RangeCamera> read_range_camera(const std::string& image_path, int width,
                                             int height, const RangeIntrinsics& intrinsics);

/// Several views of one part (their cameras put them in one frame), as read_range reads each.
std::vector<RangeScan> read_ranges(const std::vector<std::string>& paths,
                                   const RangeReadOptions& options = {});

}  // namespace csgfit
