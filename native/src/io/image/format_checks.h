// What an image file is, and whether it is whole, decided before stb sees it. stb decodes a
// JPEG, BMP or TGA whose pixel data is cut short without complaint, filling the rest with
// zeros: black, i.e. shape. These checks catch that (and a few inputs known to crash this stb
// version) before decoding.
#pragma once

#include <climits>
#include <cstdint>
#include <string>
#include <vector>

namespace csgfit::image_detail {

bool is_png(const std::string& d);
bool is_jpeg(const std::string& d);
bool is_bmp(const std::string& d);

/// Walks the PNG chunks: all must fit in the file, critical chunks (IHDR, PLTE, IDAT, IEND)
/// must have a correct CRC (stb checks none, so a flipped bit could otherwise pass as pixels),
/// and IEND must be there (a cut file). Empty IDAT chunks, which are legal but make this stb
/// version memcpy from a null pointer, are dropped into `cleaned` (left empty when there are
/// none, to avoid a copy).
bool png_is_complete(const std::string& d, std::vector<std::uint8_t>* cleaned);

enum class JpegCheck { kComplete, kTruncated, kUnsafe };

/// A complete JPEG ends its last scan with an EOI marker; kUnsafe for a scan that uses a
/// Huffman table never defined (stb would read it uninitialised), or for Huffman tables that
/// would make this stb version write past its tables (CVE-2021-37789).
JpegCheck check_jpeg(const std::string& d);

/// Uncompressed BMP: the rows must fit in the file (stb does not read RLE BMPs).
bool bmp_is_complete(const std::string& d);

/// TGA, uncompressed or RLE: the pixel data must cover width * height pixels.
bool tga_is_complete(const std::string& d);

/// a * b, or LLONG_MAX when that overflows (both >= 0): image sizes from hostile headers.
inline long long saturating_mul(long long a, long long b) {
  if (a != 0 && b > LLONG_MAX / a) return LLONG_MAX;
  return a * b;
}

}  // namespace csgfit::image_detail
