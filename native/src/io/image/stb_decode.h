// The image decoder: stb_image, compiled once in stb_decode.cpp, behind two calls.
#pragma once

#include <cstdint>
#include <memory>

#include "io/image/grey.h"

namespace csgfit::image_detail {

/// Width and height from the file's header (stbi_info); false when stb cannot read it.
bool stb_dimensions(const std::uint8_t* bytes, int size, long long* width, long long* height);

struct StbFree {
  void operator()(void* p) const;
};

/// What stb_decode made: the pixels (no data when decoding failed) and the buffer that holds
/// them.
struct StbImage {
  std::unique_ptr<void, StbFree> buffer;
  DecodedPixels pixels;
  bool too_large = false;  ///< the failure was stb's own size limit or memory
};

/// Decodes at the file's bit depth (16-bit PNGs stay 16-bit) and channel count.
StbImage stb_decode(const std::uint8_t* bytes, int size);

}  // namespace csgfit::image_detail
