// PNG output: the preview overlay and the plain bitmap, both encoded by stb_image_write and
// written atomically.

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "csgfit/io/files.h"
#include "csgfit/io/image.h"
#include "csgfit/model/memory_budget.h"
#include "io/image/format_checks.h"
#include "io/input_file.h"

// A private, static copy of the writer, so that no other object's copy can clash with it; the
// header comes from the system include path, which our warning flags skip.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace csgfit {

void write_preview_png(const std::string& path, const Bitmap& target, const Bitmap& result,
                       int scale) {
  if (target.width() != result.width() || target.height() != result.height()) {
    throw std::invalid_argument("write_preview_png: target and result differ in size");
  }
  if (target.empty()) throw std::invalid_argument("write_preview_png: empty bitmap");
  scale = std::max(scale, 1);
  const long long width = static_cast<long long>(target.width()) * scale;
  const long long height = static_cast<long long>(target.height()) * scale;
  if (width > INT_MAX / 3 || image_detail::saturating_mul(width, height) > (1LL << 28)) {
    throw std::invalid_argument("write_preview_png: preview too large");
  }
  const int stride = static_cast<int>(width) * 3;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(stride) *
                                static_cast<std::size_t>(height));
  for (int r = 0; r < target.height(); ++r) {
    for (int c = 0; c < target.width(); ++c) {
      const bool in_target = target.get(c, r);
      const bool in_result = result.get(c, r);
      std::array<std::uint8_t, 3> colour{255, 255, 255};
      if (in_target && in_result) {
        colour = {64, 64, 64};
      } else if (in_result) {
        colour = {220, 40, 40};
      } else if (in_target) {
        colour = {40, 90, 220};
      }
      for (int dy = 0; dy < scale; ++dy) {
        std::uint8_t* out = rgb.data() + static_cast<std::size_t>(r * scale + dy) * stride +
                            static_cast<std::size_t>(c) * scale * 3;
        for (int dx = 0; dx < scale; ++dx, out += 3) std::copy(colour.begin(), colour.end(), out);
      }
    }
  }
  write_rgb_png(path, static_cast<int>(width), static_cast<int>(height), rgb);
}

void write_rgb_png(const std::string& path, int width, int height,
                   const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 ||
      rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw std::invalid_argument("write_rgb_png: size and pixels disagree");
  std::string encoded;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &encoded, width, height, 3, rgb.data(), width * 3)) {
    io_detail::fail("cannot write " + io_detail::quoted(path) + ": PNG encoding failed");
  }
  write_file_atomic(path, encoded);
}

void write_bitmap_png(const std::string& path, const Bitmap& bitmap) {
  if (bitmap.empty())
    io_detail::fail("cannot write " + io_detail::quoted(path) + ": the raster is " +
                    std::to_string(bitmap.width()) + " x " + std::to_string(bitmap.height()) +
                    " pixels (nothing to draw)");
  const double pixels = static_cast<double>(bitmap.width()) * bitmap.height();
  if (pixels > static_cast<double>(1LL << 30))
    io_detail::fail("cannot write " + io_detail::quoted(path) + ": over 2^30 pixels for a PNG");
  check_allocation(2 * pixels, "a PNG of " + std::to_string(bitmap.width()) + " x " +
                                   std::to_string(bitmap.height()) + " pixels");
  std::vector<unsigned char> grey(static_cast<std::size_t>(bitmap.width()) * bitmap.height(), 255);
  for (int r = 0; r < bitmap.height(); ++r) {
    for (int c = 0; c < bitmap.width(); ++c) {
      if (bitmap.get(c, r)) grey[static_cast<std::size_t>(r) * bitmap.width() + c] = 0;
    }
  }
  int len = 0;
  unsigned char* png =
      stbi_write_png_to_mem(grey.data(), bitmap.width(), bitmap.width(), bitmap.height(), 1, &len);
  if (!png) throw std::bad_alloc();
  std::string bytes(reinterpret_cast<const char*>(png), static_cast<std::size_t>(len));
  STBIW_FREE(png);
  write_file_atomic(path, bytes);
}

}  // namespace csgfit
