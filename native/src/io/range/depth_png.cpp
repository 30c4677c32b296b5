// Depth images as 16-bit grey PNGs: value x depth_unit is the depth, the sidecar's no_return
// value (0) none. Decoded by the image reader's stb, after the same completeness checks.

#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/image/format_checks.h"
#include "io/image/stb_decode.h"
#include "io/input_file.h"
#include "io/range/range_formats.h"
#include "io/sniff.h"

namespace csgfit::io_detail {

namespace {

// PNG colour types (the IHDR byte after the bit depth).
constexpr int kGrey = 0;

struct PngHeader {
  long long width = 0, height = 0;
  int bit_depth = 0, colour_type = 0;
};

PngHeader png_header(const std::string& path, const std::string& d) {
  if (!image_detail::is_png(d)) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a PNG depth image");
    fail(quoted(path) + " is not a PNG image (no PNG signature)");
  }
  const unsigned char* b = bytes_of(d);
  if (d.size() < 29 || std::memcmp(b + 12, "IHDR", 4) != 0) {
    fail(quoted(path) + " is truncated or corrupt (no PNG IHDR chunk)");
  }
  return {be32(b + 16), be32(b + 20), b[24], b[25]};
}

void check_depth_header(const std::string& path, const PngHeader& h,
                        const RangeReadOptions& options) {
  if (h.bit_depth != 16) {
    fail(quoted(path) + " is an " + std::to_string(h.bit_depth) +
         "-bit image; a depth image must be 16-bit grey (depth = value x depth_unit)");
  }
  if (h.colour_type != kGrey) {
    fail(quoted(path) + " is a colour or grey + alpha PNG; a depth image must be 16-bit grey");
  }
  if (h.width <= 0 || h.height <= 0 || h.width > INT_MAX || h.height > INT_MAX ||
      image_detail::saturating_mul(h.width, h.height) > options.max_pixels) {
    fail(quoted(path) + " is " + std::to_string(h.width) + " x " + std::to_string(h.height) +
         " pixels, over the limit of " + std::to_string(options.max_pixels) + " pixels");
  }
}

}  // namespace

RangeScan read_depth_png(const std::string& path, const std::string& d,
                         const RangeReadOptions& options) {
  const PngHeader h = png_header(path, d);
  check_depth_header(path, h, options);
  const int width = static_cast<int>(h.width), height = static_cast<int>(h.height);
  const SidecarCamera camera = depth_camera(path, width, height, options.intrinsics);
  std::vector<std::uint8_t> cleaned;
  if (!image_detail::png_is_complete(d, &cleaned)) {
    fail(quoted(path) + " is truncated or corrupt (a PNG chunk is cut short or fails its CRC)");
  }
  const std::uint8_t* bytes = cleaned.empty() ? bytes_of(d) : cleaned.data();
  const std::size_t size = cleaned.empty() ? d.size() : cleaned.size();
  if (size > static_cast<std::size_t>(INT_MAX)) fail(quoted(path) + " is too large to decode");
  const image_detail::StbImage image = image_detail::stb_decode(bytes, static_cast<int>(size));
  const image_detail::DecodedPixels& px = image.pixels;
  if (!image.buffer || !px.sixteen_bit || px.channels != 1 || px.width != width ||
      px.height != height) {
    fail(quoted(path) + " is not a PNG stb can decode (truncated or corrupt?)");
  }
  const auto* values = static_cast<const std::uint16_t*>(px.data);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> depth(static_cast<std::size_t>(width) * height);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    depth[i] = values[i] == camera.no_return ? nan : values[i] * camera.camera.depth_unit;
  }
  return scan_from_depth(path, camera.camera, depth);
}

RangeScan scan_from_depth(const std::string& path, const RangeCamera& camera,
                          const std::vector<double>& depth) {
  RangeScan scan;
  scan.source = path;
  scan.camera = camera;
  scan.width = camera.width;
  scan.height = camera.height;
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const int i = v * camera.width + u;
      const double z = depth[static_cast<std::size_t>(i)];
      if (!std::isfinite(z) || !(z > 0)) {
        ++scan.dropped_no_return;
        continue;
      }
      scan.points.push_back(camera.world_point(u, v, z));
      scan.pixel.push_back(i);
    }
  }
  check_has_returns(scan);
  return scan;
}

void check_has_returns(const RangeScan& scan) {
  if (!scan.points.empty()) return;
  fail(quoted(scan.source) + " has no returns: " +
       (scan.organised() ? "every one of its " + count_text(scan.dropped_no_return, "pixel") +
                               " is empty (0 or NaN)"
                         : std::string("it holds no finite point")));
}

}  // namespace csgfit::io_detail
