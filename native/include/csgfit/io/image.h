// Reading bitmaps from image files, thresholding them, and writing preview images.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/model/bitmap.h"

namespace csgfit {

/// A decoded image reduced to 8-bit grey plus an optional 8-bit alpha (empty when the file has
/// none). 16-bit, palette, grey+alpha, RGB and RGBA files all arrive in this form.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> grey;   ///< width * height, row 0 at the top
  std::vector<std::uint8_t> alpha;  ///< width * height or empty
};

/// Limits and thresholding for turning a file into a target bitmap.
struct ImageReadOptions {
  int threshold = -1;        ///< grey level; pixels darker than or equal to it are shape. < 0 = Otsu
  bool invert = false;       ///< light pixels are the shape
  long long max_pixels = 4096LL * 4096LL;  ///< refuse larger images (InputError names the limit)
  int max_size = 0;          ///< > 0: downsample so that neither side exceeds it (area average)
};

/// Decodes PNG, JPEG, BMP, PGM/PPM/PBM and TGA. Throws InputError (one line, naming the file)
/// for a missing, unreadable, truncated or non-image file and for an image over the limits.
GreyImage read_image(const std::string& path, const ImageReadOptions& options = {});

/// Otsu's threshold of the grey levels (of the opaque pixels when there is alpha).
int otsu_threshold(const GreyImage& image);

/// Shape pixels: dark (or light with invert) and not transparent (alpha < 128 is background).
Bitmap threshold_image(const GreyImage& image, const ImageReadOptions& options = {});

/// read_image + threshold_image.
Bitmap read_bitmap(const std::string& path, const ImageReadOptions& options = {});

/// Writes a PNG: target and result overlaid: matched shape dark grey, excess pixels (result
/// but not target) red, uncovered pixels (target but not result) blue, background white.
/// `scale` > 1 enlarges each pixel. Written atomically (temporary file + rename).
void write_preview_png(const std::string& path, const Bitmap& target, const Bitmap& result,
                       int scale = 1);

/// Writes 8-bit RGB pixels (row 0 at the top, width * height * 3 bytes) as a PNG, atomically.
void write_rgb_png(const std::string& path, int width, int height,
                   const std::vector<std::uint8_t>& rgb);

/// Writes frames of one size as a looping animated GIF, black shape on white, each pixel
/// `scale` x `scale`, `delay_cs` hundredths of a second a frame, atomically.
void write_bitmaps_gif(const std::string& path, const std::vector<Bitmap>& frames, int scale,
                       int delay_cs);

/// Writes a bitmap as a black-on-white 8-bit grey PNG (shape black), atomically.
void write_bitmap_png(const std::string& path, const Bitmap& bitmap);


}  // namespace csgfit
