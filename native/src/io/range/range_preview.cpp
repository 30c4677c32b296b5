#include "csgfit/io/range_preview.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "csgfit/eval/range_view.h"
#include "csgfit/io/image.h"

namespace csgfit {

namespace {

using Rgb = std::array<std::uint8_t, 3>;

// Well-separated colours for neighbouring patch numbers (golden-angle hues).
Rgb patch_colour(int patch) {
  const double h = std::fmod(patch * 0.618033988749895, 1.0) * 6.0;
  const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  const auto level = [](double v) { return static_cast<std::uint8_t>(60 + 180 * v); };
  return {level(r), level(g), level(b)};
}

Rgb error_colour(double error, double full_scale) {
  const double t = std::clamp(error / full_scale, 0.0, 1.0);
  const auto fade = static_cast<std::uint8_t>(255 * (1 - t));
  return {255, fade, fade};
}

}  // namespace

void write_range_preview(const std::string& path, const RangeScan& scan,
                         const RangeFitResult& result) {
  if (!scan.camera || !scan.organised()) throw std::invalid_argument("write_range_preview: no camera");
  const int w = scan.width, h = scan.height;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(2 * w) * h * 3, 0);
  const auto put = [&](int x, int y, const Rgb& c) {
    std::copy(c.begin(), c.end(), rgb.begin() + (static_cast<std::ptrdiff_t>(y) * 2 * w + x) * 3);
  };
  std::vector<double> seen(static_cast<std::size_t>(w) * h, 0.0);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const int px = scan.pixel[i];
    const int patch = i < result.patch_of_point.size() ? result.patch_of_point[i] : -1;
    put(px % w, px / w, patch < 0 ? Rgb{128, 128, 128} : patch_colour(patch));
    seen[px] = scan.camera->project(scan.points[i])[2];
  }
  const std::vector<double> depth = tree_depth_map(result.tree, *scan.camera, 1e-4 * result.diagonal);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t px = static_cast<std::size_t>(y) * w + x;
      if (seen[px] > 0 && depth[px] > 0)
        put(w + x, y, error_colour(std::abs(seen[px] - depth[px]), 0.01 * result.diagonal));
      else if (depth[px] > 0)
        put(w + x, y, {40, 90, 220});
      else if (seen[px] > 0)
        put(w + x, y, {255, 0, 0});
    }
  write_rgb_png(path, 2 * w, h, rgb);
}

}  // namespace csgfit
