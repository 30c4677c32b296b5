// read_image: the file's header gives the size, which is checked against the limits before
// anything is decoded; then Netpbm is decoded by netpbm.cpp and the rest, once checked whole,
// by stb.

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "csgfit/io/image.h"
#include "io/byte_order.h"
#include "io/image/format_checks.h"
#include "io/image/grey.h"
#include "io/image/netpbm.h"
#include "io/image/stb_decode.h"
#include "io/input_file.h"

namespace csgfit::image_detail {

namespace {

using io_detail::be32;
using io_detail::bytes_of;
using io_detail::fail;
using io_detail::le32;
using io_detail::quoted;

// With --max-size the image is decoded at full size before it is downsampled, so the decode
// needs its own bound: this many times max_pixels (1G pixels with the default limit).
constexpr long long kDecodeLimitFactor = 64;

// stb takes buffer lengths as int.
constexpr long long kMaxFileBytes = INT_MAX;

[[noreturn]] void fail_not_an_image(const std::string& path) {
  fail(quoted(path) + " is not an image stb can decode (truncated or corrupt?)");
}

std::string size_text(long long width, long long height) {
  return std::to_string(width) + " x " + std::to_string(height) + " pixels";
}

enum class Format { kNetpbm, kPng, kJpeg, kBmp, kTga };

struct ImageHeader {
  Format format = Format::kTga;
  JpegCheck jpeg_check = JpegCheck::kComplete;
  long long width = 0;
  long long height = 0;
  NetpbmHeader netpbm;
};

// The format and size from the header alone, so that the limits are checked before anything
// is allocated.
ImageHeader read_header(const std::string& path, const std::string& file) {
  ImageHeader h;
  const std::uint8_t* bytes = bytes_of(file);
  if (looks_like_netpbm(bytes, file.size())) {
    h.format = Format::kNetpbm;
    std::string reason;
    if (!parse_netpbm_header(bytes, file.size(), &h.netpbm, &reason)) {
      fail(quoted(path) + " is not a valid Netpbm image (" + reason + ")");
    }
    h.width = h.netpbm.width;
    h.height = h.netpbm.height;
  } else if (is_png(file) && file.size() >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
    // Read IHDR ourselves: stbi_info refuses large PNGs with a reason we could not report.
    h.format = Format::kPng;
    h.width = be32(bytes + 16);
    h.height = be32(bytes + 20);
  } else {
    h.format = is_png(file)    ? Format::kPng
               : is_jpeg(file) ? Format::kJpeg
               : is_bmp(file)  ? Format::kBmp
                               : Format::kTga;
    // stb reads no run-length compressed BMP (ImageMagick writes them for grey images).
    if (h.format == Format::kBmp && file.size() >= 34 && le32(bytes + 14) >= 40 &&
        (le32(bytes + 30) == 1 || le32(bytes + 30) == 2)) {
      fail(quoted(path) +
           " is a run-length compressed BMP, which is not supported (save it "
           "uncompressed or as PNG)");
    }
    // stbi_info already parses the JPEG tables, so the unsafe ones must be refused before,
    // and so must a cut one: stb reads the tables of a segment cut short too (fuzz/).
    if (h.format == Format::kJpeg) h.jpeg_check = check_jpeg(file);
    if (h.jpeg_check != JpegCheck::kComplete) fail_not_an_image(path);
    if (!stb_dimensions(bytes, static_cast<int>(file.size()), &h.width, &h.height)) {
      fail_not_an_image(path);
    }
    // A negative BMP height is a top-down image, which stb decodes; its stbi_info does not
    // drop the sign.
    if (h.format == Format::kBmp) h.height = std::llabs(h.height);
  }
  if (h.width <= 0 || h.height <= 0) fail(quoted(path) + " is " + size_text(h.width, h.height));
  return h;
}

// The output size: downsampled so that neither side exceeds max_size, keeping the aspect
// ratio. Refuses an image over the limits, before or after downsampling.
void output_size(const std::string& path, const ImageHeader& h, const ImageReadOptions& options,
                 long long* out_width, long long* out_height) {
  const long long width = h.width;
  const long long height = h.height;
  *out_width = width;
  *out_height = height;
  const long long max_size = options.max_size;
  if (max_size > 0 && (width > max_size || height > max_size)) {
    if (width >= height) {
      *out_width = max_size;
      *out_height = std::max(1LL, (saturating_mul(height, max_size) + width / 2) / width);
    } else {
      *out_height = max_size;
      *out_width = std::max(1LL, (saturating_mul(width, max_size) + height / 2) / height);
    }
  }
  const long long pixels = saturating_mul(width, height);
  const long long limit = options.max_pixels;
  if (*out_width == width && *out_height == height) {
    if (pixels > limit) {
      fail(quoted(path) + " is " + size_text(width, height) + ", over the limit of " +
           std::to_string(limit) + " pixels" +
           (max_size > 0 ? "" : " (use --max-size to downsample)"));
    }
  } else {
    const long long decode_limit = saturating_mul(limit, kDecodeLimitFactor);
    if (pixels > decode_limit) {
      fail(quoted(path) + " is " + size_text(width, height) + ", over the limit of " +
           std::to_string(decode_limit) + " pixels that can be decoded even with --max-size");
    }
    if (saturating_mul(*out_width, *out_height) > limit) {
      fail(quoted(path) + " downsampled to " + size_text(*out_width, *out_height) +
           " is still over the limit of " + std::to_string(limit) + " pixels");
    }
  }
  if (width > INT_MAX || height > INT_MAX) {  // only with an absurd --max-pixels
    fail(quoted(path) + " is " + size_text(width, height) + ", too large to decode");
  }
}

GreyImage decode_netpbm_image(const std::string& path, const std::string& file,
                              const ImageHeader& h, int out_width, int out_height) {
  std::vector<std::uint8_t> raster;
  std::string reason;
  if (!decode_netpbm(bytes_of(file), file.size(), h.netpbm, &raster, &reason)) {
    fail(quoted(path) + " is not a valid Netpbm image (" + reason + ")");
  }
  DecodedPixels decoded;
  decoded.width = static_cast<int>(h.width);
  decoded.height = static_cast<int>(h.height);
  decoded.channels = h.netpbm.channels;
  decoded.data = raster.data();
  return to_grey_image(decoded, out_width, out_height);
}

GreyImage decode_stb_image(const std::string& path, const std::string& file, const ImageHeader& h,
                           int out_width, int out_height) {
  std::vector<std::uint8_t> cleaned_png;
  if ((h.format == Format::kPng && !png_is_complete(file, &cleaned_png)) ||
      (h.format == Format::kJpeg && h.jpeg_check != JpegCheck::kComplete) ||
      (h.format == Format::kBmp && !bmp_is_complete(file)) ||
      (h.format == Format::kTga && !tga_is_complete(file))) {
    fail_not_an_image(path);
  }
  const std::uint8_t* bytes = cleaned_png.empty() ? bytes_of(file) : cleaned_png.data();
  const std::size_t byte_count = cleaned_png.empty() ? file.size() : cleaned_png.size();
  const StbImage image = stb_decode(bytes, static_cast<int>(byte_count));
  if (!image.buffer) {
    if (image.too_large) {
      fail(quoted(path) + " is " + size_text(h.width, h.height) + ", too large to decode");
    }
    fail_not_an_image(path);
  }
  const DecodedPixels& decoded = image.pixels;
  if (decoded.width != h.width || decoded.height != h.height || decoded.channels < 1 ||
      decoded.channels > 4) {
    fail_not_an_image(path);
  }
  return to_grey_image(decoded, out_width, out_height);
}

}  // namespace

}  // namespace csgfit::image_detail

namespace csgfit {

GreyImage read_image(const std::string& path, const ImageReadOptions& options) {
  namespace detail = image_detail;
  const std::string file =
      io_detail::read_whole_file(path, detail::kMaxFileBytes, "too large to decode");
  const detail::ImageHeader header = detail::read_header(path, file);
  long long out_width = 0;
  long long out_height = 0;
  detail::output_size(path, header, options, &out_width, &out_height);
  if (header.format == detail::Format::kNetpbm) {
    return detail::decode_netpbm_image(path, file, header, static_cast<int>(out_width),
                                       static_cast<int>(out_height));
  }
  return detail::decode_stb_image(path, file, header, static_cast<int>(out_width),
                                  static_cast<int>(out_height));
}

}  // namespace csgfit
