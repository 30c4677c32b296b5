#include "io/image/stb_decode.h"

#include <cstring>

// stb is compiled here with static linkage, so another object that embeds stb cannot clash with
// it, and with only the formats we document (less code that parses untrusted bytes). Netpbm is
// read by netpbm.cpp instead of stb's PNM reader (see there why). The header is included as
// <stb/...> so that it comes from the system include path and our warning flags skip it.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#include <stb/stb_image.h>

namespace csgfit::image_detail {

bool stb_dimensions(const std::uint8_t* bytes, int size, long long* width, long long* height) {
  int w = 0;
  int h = 0;
  int channels = 0;
  if (!stbi_info_from_memory(bytes, size, &w, &h, &channels)) return false;
  *width = w;
  *height = h;
  return true;
}

void StbFree::operator()(void* p) const { stbi_image_free(p); }

StbImage stb_decode(const std::uint8_t* bytes, int size) {
  StbImage image;
  int w = 0;
  int h = 0;
  int channels = 0;
  if (stbi_is_16_bit_from_memory(bytes, size)) {
    image.buffer.reset(stbi_load_16_from_memory(bytes, size, &w, &h, &channels, 0));
    image.pixels.sixteen_bit = true;
  } else {
    image.buffer.reset(stbi_load_from_memory(bytes, size, &w, &h, &channels, 0));
  }
  if (!image.buffer) {
    const char* reason = stbi_failure_reason();
    image.too_large = reason != nullptr && (std::strcmp(reason, "too large") == 0 ||
                                            std::strcmp(reason, "outofmem") == 0);
    return image;
  }
  image.pixels.width = w;
  image.pixels.height = h;
  image.pixels.channels = channels;
  image.pixels.data = image.buffer.get();
  return image;
}

}  // namespace csgfit::image_detail
