// A private, static copy of the writer: no clash with another translation unit's.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include <new>
#include <string>
#include <vector>

#include "csgfit/io/image.h"
#include "csgfit/io/files.h"

namespace csgfit {

void write_bitmap_png(const std::string& path, const Bitmap& bitmap) {
  std::vector<unsigned char> grey(static_cast<std::size_t>(bitmap.width()) * bitmap.height(), 255);
  for (int r = 0; r < bitmap.height(); ++r)
    for (int c = 0; c < bitmap.width(); ++c)
      if (bitmap.get(c, r)) grey[static_cast<std::size_t>(r) * bitmap.width() + c] = 0;
  int len = 0;
  unsigned char* png = stbi_write_png_to_mem(grey.data(), bitmap.width(), bitmap.width(),
                                             bitmap.height(), 1, &len);
  if (!png) throw std::bad_alloc();
  std::string bytes(reinterpret_cast<const char*>(png), static_cast<std::size_t>(len));
  STBIW_FREE(png);
  write_file_atomic(path, bytes);
}

}  // namespace csgfit
