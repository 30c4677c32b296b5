// Decoded pixels to the 8-bit grey (+ alpha) image the fit works on, downsampled on the way
// when asked.
#pragma once

#include <cstdint>

#include "csgfit/io/image.h"

namespace csgfit::image_detail {

/// Decoded pixels in one of stb's layouts: 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA)
/// interleaved channels of 8 or 16 bits, row 0 at the top.
struct DecodedPixels {
  int width = 0;
  int height = 0;
  int channels = 0;
  bool sixteen_bit = false;
  const void* data = nullptr;

  bool has_alpha() const { return channels == 2 || channels == 4; }

  /// Grey (luma) and alpha of one row, 8 bits each; `alpha` may be null.
  void convert_row(int row, std::uint8_t* grey, std::uint8_t* alpha) const;

 private:
  template <typename T, typename To8>
  void convert(const T* in, std::uint8_t* grey, std::uint8_t* alpha, To8 to8) const;
};

/// The image at out_width x out_height (area average when smaller than the pixels).
GreyImage to_grey_image(const DecodedPixels& pixels, int out_width, int out_height);

}  // namespace csgfit::image_detail
