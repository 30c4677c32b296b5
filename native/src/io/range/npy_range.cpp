// Range data as NumPy arrays: an H x W depth map (NaN = no return) that its sidecar turns into
// points, or an H x W x 3 organised cloud already in model coordinates.

#include <sys/stat.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/npy_array.h"
#include "io/range/range_formats.h"

namespace csgfit::io_detail {

namespace {

// Where element (v, u, c) of an H x W (x C) array is, in items, for either order.
struct NpyLayout {
  std::size_t height, width, channels;
  bool fortran;

  std::size_t at(std::size_t v, std::size_t u, std::size_t c) const {
    return fortran ? (c * width + u) * height + v : (v * width + u) * channels + c;
  }
};

NpyLayout range_layout(const std::string& path, const std::string& d, const NpyHeader& h,
                       const RangeReadOptions& options) {
  const auto& s = h.shape;
  const bool depth = s.size() == 2, cloud = s.size() == 3 && s[2] == 3;
  if (!depth && !cloud) {
    fail(quoted(path) + " has shape " + npy_shape_text(s) +
         ": a range .npy is an H x W depth map or an H x W x 3 point cloud");
  }
  if (h.kind != 'f') {
    fail(quoted(path) + " holds " + h.descr + " values: a range .npy must be float32 or float64");
  }
  const unsigned long long limit = static_cast<unsigned long long>(options.max_pixels);
  if (s[0] == 0 || s[1] == 0 || s[0] > limit || s[1] > limit || s[0] * s[1] > limit) {
    fail(quoted(path) + " has shape " + npy_shape_text(s) + ", " +
         (s[0] == 0 || s[1] == 0 ? std::string("an empty image")
                                 : "over the limit of " + std::to_string(limit) + " pixels"));
  }
  const NpyLayout l{static_cast<std::size_t>(s[0]), static_cast<std::size_t>(s[1]),
                    cloud ? 3u : 1u, h.fortran};
  check_npy_data_size(path, d, h, s[0] * s[1] * l.channels);
  return l;
}

// The view of a sidecar of the cloud's size next to it, to turn the normals by.
std::optional<Vec3> cloud_view(const std::string& path, int width, int height) {
  std::vector<std::string> candidates{sidecar_path(path)};
  const std::string suffix = "_xyz.npy";
  if (path.size() > suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(),
                                                  suffix) == 0) {
    candidates.push_back(path.substr(0, path.size() - suffix.size()) + "_ortho.json");
  }
  for (const std::string& json : candidates) {
    struct stat st {};
    if (::stat(json.c_str(), &st) != 0) continue;
    try {
      const auto camera = read_sidecar_camera(json, width, height, {});
      if (camera) return camera->camera.view_direction();
    } catch (const InputError&) {
      // Another image's sidecar (another size): it says nothing about this cloud.
    }
  }
  return std::nullopt;
}

RangeScan read_cloud(const std::string& path, const std::string& d, const NpyHeader& h,
                     const NpyLayout& l) {
  RangeScan scan;
  scan.source = path;
  scan.width = static_cast<int>(l.width);
  scan.height = static_cast<int>(l.height);
  const unsigned char* data = bytes_of(d) + h.data_start;
  for (std::size_t v = 0; v < l.height; ++v) {
    for (std::size_t u = 0; u < l.width; ++u) {
      Vec3 p;
      for (std::size_t c = 0; c < 3; ++c) p[c] = npy_value(h, data + l.at(v, u, c) * h.item_size);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
        ++scan.dropped_no_return;
        continue;
      }
      scan.points.push_back(p);
      scan.pixel.push_back(static_cast<int>(v * l.width + u));
    }
  }
  check_has_returns(scan);
  return scan;
}

}  // namespace

RangeScan read_npy_range(const std::string& path, const std::string& d,
                         const RangeReadOptions& options, std::optional<Vec3>* view_direction) {
  const NpyHeader h = read_npy_header(path, d, "range image");
  const NpyLayout l = range_layout(path, d, h, options);
  const int width = static_cast<int>(l.width), height = static_cast<int>(l.height);
  if (l.channels == 3) {
    *view_direction = cloud_view(path, width, height);
    return read_cloud(path, d, h, l);
  }
  const SidecarCamera camera = depth_camera(path, width, height, options.intrinsics);
  std::vector<double> depth(l.width * l.height);
  const unsigned char* data = bytes_of(d) + h.data_start;
  for (std::size_t v = 0; v < l.height; ++v) {
    for (std::size_t u = 0; u < l.width; ++u) {
      depth[v * l.width + u] = npy_value(h, data + l.at(v, u, 0) * h.item_size);
    }
  }
  return scan_from_depth(path, camera.camera, depth);
}

}  // namespace csgfit::io_detail
