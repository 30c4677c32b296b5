// Image input/output: every supported format decodes to the expected bitmap, bad files give a
// one-line InputError naming the file, limits are checked before decoding, writes are atomic.
#include "csgfit/io/image.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "hand_png.h"

// Private copies of stb for making fixtures and reading the preview back.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace csgfit {
namespace {

namespace fs = std::filesystem;
using testing::be32;
using testing::crc32;
using testing::le16;
using testing::make_png;
using testing::png_chunk;
using testing::zlib_stored;

// ---------------------------------------------------------------------------------------------
// Fixture helpers

// A small pattern with shape pixels on every row and column, asymmetric so that flips and
// transposes show up. Width 10 is not a multiple of 8 (PBM P4 row padding).
constexpr int kW = 10;
constexpr int kH = 6;
bool pattern(int c, int r) { return (c + 2 * r) % 3 == 0 || c == kW - 1 || (r == 0 && c < 3); }

Bitmap pattern_bitmap() {
  Bitmap b(kW, kH);
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c)
      if (pattern(c, r)) b.set(c, r);
  return b;
}

std::string bitmap_text(const Bitmap& b) {
  std::string s;
  for (int r = 0; r < b.height(); ++r) {
    for (int c = 0; c < b.width(); ++c) s += b.get(c, r) ? '#' : '.';
    s += '\n';
  }
  return s;
}

void expect_pattern(const Bitmap& b) {
  ASSERT_EQ(b.width(), kW);
  ASSERT_EQ(b.height(), kH);
  EXPECT_EQ(bitmap_text(b), bitmap_text(pattern_bitmap()));
}

// A 32 x 32 JPEG (quality 90, colour): 8 x 8 checkerboard, dark blue (20,20,120) where
// (c/8 + r/8) is odd, light yellow (250,240,180) elsewhere. Embedded rather than made with
// stb_image_write, whose JPEG encoder shifts negative ints (UBSan fails the sanitizer build).
const unsigned char kCheckerJpeg[] = {
    0xff, 0xd8, 0xff, 0xe0, 0x00, 0x10, 0x4a, 0x46, 0x49, 0x46, 0x00, 0x01, 0x01, 0x00, 0x00, 0x01,
    0x00, 0x01, 0x00, 0x00, 0xff, 0xdb, 0x00, 0x84, 0x00, 0x03, 0x02, 0x02, 0x03, 0x02, 0x02, 0x03,
    0x03, 0x03, 0x03, 0x04, 0x03, 0x03, 0x04, 0x05, 0x08, 0x05, 0x05, 0x04, 0x04, 0x05, 0x0a, 0x07,
    0x07, 0x06, 0x08, 0x0c, 0x0a, 0x0c, 0x0c, 0x0b, 0x0a, 0x0b, 0x0b, 0x0d, 0x0e, 0x12, 0x10, 0x0d,
    0x0e, 0x11, 0x0e, 0x0b, 0x0b, 0x10, 0x16, 0x10, 0x11, 0x13, 0x14, 0x15, 0x15, 0x15, 0x0c, 0x0f,
    0x17, 0x18, 0x16, 0x14, 0x18, 0x12, 0x14, 0x15, 0x14, 0x01, 0x03, 0x04, 0x04, 0x05, 0x04, 0x05,
    0x09, 0x05, 0x05, 0x09, 0x14, 0x0d, 0x0b, 0x0d, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14,
    0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14,
    0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14,
    0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0x14, 0xff, 0xc0, 0x00, 0x11, 0x08, 0x00,
    0x20, 0x00, 0x20, 0x03, 0x01, 0x22, 0x00, 0x02, 0x11, 0x01, 0x03, 0x11, 0x01, 0xff, 0xc4, 0x01,
    0xa2, 0x00, 0x00, 0x01, 0x05, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0a, 0x0b, 0x10, 0x00,
    0x02, 0x01, 0x03, 0x03, 0x02, 0x04, 0x03, 0x05, 0x05, 0x04, 0x04, 0x00, 0x00, 0x01, 0x7d, 0x01,
    0x02, 0x03, 0x00, 0x04, 0x11, 0x05, 0x12, 0x21, 0x31, 0x41, 0x06, 0x13, 0x51, 0x61, 0x07, 0x22,
    0x71, 0x14, 0x32, 0x81, 0x91, 0xa1, 0x08, 0x23, 0x42, 0xb1, 0xc1, 0x15, 0x52, 0xd1, 0xf0, 0x24,
    0x33, 0x62, 0x72, 0x82, 0x09, 0x0a, 0x16, 0x17, 0x18, 0x19, 0x1a, 0x25, 0x26, 0x27, 0x28, 0x29,
    0x2a, 0x34, 0x35, 0x36, 0x37, 0x38, 0x39, 0x3a, 0x43, 0x44, 0x45, 0x46, 0x47, 0x48, 0x49, 0x4a,
    0x53, 0x54, 0x55, 0x56, 0x57, 0x58, 0x59, 0x5a, 0x63, 0x64, 0x65, 0x66, 0x67, 0x68, 0x69, 0x6a,
    0x73, 0x74, 0x75, 0x76, 0x77, 0x78, 0x79, 0x7a, 0x83, 0x84, 0x85, 0x86, 0x87, 0x88, 0x89, 0x8a,
    0x92, 0x93, 0x94, 0x95, 0x96, 0x97, 0x98, 0x99, 0x9a, 0xa2, 0xa3, 0xa4, 0xa5, 0xa6, 0xa7, 0xa8,
    0xa9, 0xaa, 0xb2, 0xb3, 0xb4, 0xb5, 0xb6, 0xb7, 0xb8, 0xb9, 0xba, 0xc2, 0xc3, 0xc4, 0xc5, 0xc6,
    0xc7, 0xc8, 0xc9, 0xca, 0xd2, 0xd3, 0xd4, 0xd5, 0xd6, 0xd7, 0xd8, 0xd9, 0xda, 0xe1, 0xe2, 0xe3,
    0xe4, 0xe5, 0xe6, 0xe7, 0xe8, 0xe9, 0xea, 0xf1, 0xf2, 0xf3, 0xf4, 0xf5, 0xf6, 0xf7, 0xf8, 0xf9,
    0xfa, 0x01, 0x00, 0x03, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0a, 0x0b, 0x11, 0x00,
    0x02, 0x01, 0x02, 0x04, 0x04, 0x03, 0x04, 0x07, 0x05, 0x04, 0x04, 0x00, 0x01, 0x02, 0x77, 0x00,
    0x01, 0x02, 0x03, 0x11, 0x04, 0x05, 0x21, 0x31, 0x06, 0x12, 0x41, 0x51, 0x07, 0x61, 0x71, 0x13,
    0x22, 0x32, 0x81, 0x08, 0x14, 0x42, 0x91, 0xa1, 0xb1, 0xc1, 0x09, 0x23, 0x33, 0x52, 0xf0, 0x15,
    0x62, 0x72, 0xd1, 0x0a, 0x16, 0x24, 0x34, 0xe1, 0x25, 0xf1, 0x17, 0x18, 0x19, 0x1a, 0x26, 0x27,
    0x28, 0x29, 0x2a, 0x35, 0x36, 0x37, 0x38, 0x39, 0x3a, 0x43, 0x44, 0x45, 0x46, 0x47, 0x48, 0x49,
    0x4a, 0x53, 0x54, 0x55, 0x56, 0x57, 0x58, 0x59, 0x5a, 0x63, 0x64, 0x65, 0x66, 0x67, 0x68, 0x69,
    0x6a, 0x73, 0x74, 0x75, 0x76, 0x77, 0x78, 0x79, 0x7a, 0x82, 0x83, 0x84, 0x85, 0x86, 0x87, 0x88,
    0x89, 0x8a, 0x92, 0x93, 0x94, 0x95, 0x96, 0x97, 0x98, 0x99, 0x9a, 0xa2, 0xa3, 0xa4, 0xa5, 0xa6,
    0xa7, 0xa8, 0xa9, 0xaa, 0xb2, 0xb3, 0xb4, 0xb5, 0xb6, 0xb7, 0xb8, 0xb9, 0xba, 0xc2, 0xc3, 0xc4,
    0xc5, 0xc6, 0xc7, 0xc8, 0xc9, 0xca, 0xd2, 0xd3, 0xd4, 0xd5, 0xd6, 0xd7, 0xd8, 0xd9, 0xda, 0xe2,
    0xe3, 0xe4, 0xe5, 0xe6, 0xe7, 0xe8, 0xe9, 0xea, 0xf2, 0xf3, 0xf4, 0xf5, 0xf6, 0xf7, 0xf8, 0xf9,
    0xfa, 0xff, 0xda, 0x00, 0x0c, 0x03, 0x01, 0x00, 0x02, 0x11, 0x03, 0x11, 0x00, 0x3f, 0x00, 0xfd,
    0x20, 0xaf, 0xe7, 0x76, 0x8a, 0xfe, 0x88, 0xab, 0xd8, 0xff, 0x00, 0x93, 0x79, 0xff, 0x00, 0x4f,
    0xfd, 0xbf, 0xfd, 0xb9, 0xcb, 0xc9, 0xff, 0x00, 0x81, 0xde, 0xfc, 0xfe, 0x56, 0xb7, 0x5b, 0xe9,
    0x5f, 0xef, 0xff, 0x00, 0xdd, 0xe5, 0xf9, 0xef, 0xf7, 0x76, 0x0a, 0xfe, 0x77, 0x68, 0xaf, 0xe8,
    0x8a, 0x8f, 0xf9, 0x37, 0x9f, 0xf4, 0xff, 0x00, 0xdb, 0xff, 0x00, 0xdb, 0x9c, 0xbc, 0x9f, 0xf8,
    0x1d, 0xef, 0xcf, 0xe5, 0x6b, 0x75, 0xbe, 0x87, 0xfb, 0xff, 0x00, 0xf7, 0x79, 0x7e, 0x7b, 0xfd,
    0xdd, 0x82, 0xbf, 0x9d, 0xda, 0x2b, 0xfa, 0x22, 0xa3, 0xfe, 0x4d, 0xe7, 0xfd, 0x3f, 0xf6, 0xff,
    0x00, 0xf6, 0xe7, 0x2f, 0x27, 0xfe, 0x07, 0x7b, 0xf3, 0xf9, 0x5a, 0xdd, 0x6f, 0xa1, 0xfe, 0xff,
    0x00, 0xfd, 0xde, 0x5f, 0x9e, 0xff, 0x00, 0x77, 0x60, 0xaf, 0xe7, 0x76, 0x8a, 0xfe, 0x88, 0xa8,
    0xff, 0x00, 0x93, 0x79, 0xff, 0x00, 0x4f, 0xfd, 0xbf, 0xfd, 0xb9, 0xcb, 0xc9, 0xff, 0x00, 0x81,
    0xde, 0xfc, 0xfe, 0x56, 0xb7, 0x5b, 0xe8, 0x7f, 0xbf, 0xff, 0x00, 0x77, 0x97, 0xe7, 0xbf, 0xdd,
    0xd8, 0xff, 0xd9,
};

std::string checker_jpeg() {
  return std::string(reinterpret_cast<const char*>(kCheckerJpeg), sizeof kCheckerJpeg);
}

class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/csgfit-image-io-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }

  static std::string read(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  // Pixels of the pattern in `channels` 8-bit channels: shape dark, background light.
  static std::vector<unsigned char> pattern_pixels(int channels, const std::array<int, 4>& dark,
                                                   const std::array<int, 4>& light) {
    std::vector<unsigned char> px;
    for (int r = 0; r < kH; ++r)
      for (int c = 0; c < kW; ++c)
        for (int k = 0; k < channels; ++k)
          px.push_back(static_cast<unsigned char>(pattern(c, r) ? dark[k] : light[k]));
    return px;
  }

  // The InputError message of read_image(file), checked to be one line naming the file.
  static std::string error_of(const std::string& file, const ImageReadOptions& options = {}) {
    try {
      read_image(file, options);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_NE(message.find("'" + file + "'"), std::string::npos) << message;
      return message;
    }
    ADD_FAILURE() << "no InputError for " << file;
    return "";
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// Formats

TEST_F(ImageIoTest, PngGrey) {
  const auto px = pattern_pixels(1, {0}, {255});
  ASSERT_TRUE(stbi_write_png(path("a.png").c_str(), kW, kH, 1, px.data(), kW));
  const GreyImage image = read_image(path("a.png"));
  EXPECT_TRUE(image.alpha.empty());
  EXPECT_EQ(image.grey[0], 0);
  expect_pattern(read_bitmap(path("a.png")));
}

TEST_F(ImageIoTest, PngGreyAlphaTransparentIsBackground) {
  // Background pixels are black too, but transparent: only the alpha separates them.
  std::vector<unsigned char> px;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      px.push_back(0);
      px.push_back(pattern(c, r) ? 255 : 0);
    }
  ASSERT_TRUE(stbi_write_png(path("ga.png").c_str(), kW, kH, 2, px.data(), kW * 2));
  const GreyImage image = read_image(path("ga.png"));
  ASSERT_EQ(image.alpha.size(), static_cast<std::size_t>(kW * kH));
  expect_pattern(read_bitmap(path("ga.png")));
}

TEST_F(ImageIoTest, PngRgbUsesLuma) {
  const auto px = pattern_pixels(3, {20, 20, 120}, {250, 240, 180});
  ASSERT_TRUE(stbi_write_png(path("rgb.png").c_str(), kW, kH, 3, px.data(), kW * 3));
  const GreyImage image = read_image(path("rgb.png"));
  EXPECT_TRUE(image.alpha.empty());
  EXPECT_EQ(image.grey[0], (299 * 20 + 587 * 20 + 114 * 120 + 500) / 1000);
  expect_pattern(read_bitmap(path("rgb.png")));
}

TEST_F(ImageIoTest, PngRgbaWithTransparentPixels) {
  // Shape: opaque dark red. Background: half opaque white, half fully transparent *black*.
  std::vector<unsigned char> px;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      if (pattern(c, r)) {
        px.insert(px.end(), {90, 0, 0, 255});
      } else if ((c + r) % 2) {
        px.insert(px.end(), {255, 255, 255, 255});
      } else {
        px.insert(px.end(), {0, 0, 0, 0});
      }
    }
  ASSERT_TRUE(stbi_write_png(path("rgba.png").c_str(), kW, kH, 4, px.data(), kW * 4));
  const GreyImage image = read_image(path("rgba.png"));
  ASSERT_EQ(image.alpha.size(), static_cast<std::size_t>(kW * kH));
  expect_pattern(read_bitmap(path("rgba.png")));
  // Transparent pixels stay background with --invert too.
  ImageReadOptions inverted;
  inverted.invert = true;
  const Bitmap b = read_bitmap(path("rgba.png"), inverted);
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c)
      EXPECT_EQ(b.get(c, r), !pattern(c, r) && (c + r) % 2 == 1) << c << "," << r;
}

TEST_F(ImageIoTest, PalettePngWithTransparency) {
  // Palette: 0 = white, 1 = black, 2 = black but transparent (tRNS).
  std::vector<std::string> rows;
  for (int r = 0; r < kH; ++r) {
    std::string row;
    for (int c = 0; c < kW; ++c) row += static_cast<char>(pattern(c, r) ? 1 : (c == 4 ? 2 : 0));
    rows.push_back(row);
  }
  const std::string plte("\xff\xff\xff\x00\x00\x00\x00\x00\x00", 9);
  const std::string trns("\xff\xff\x00", 3);
  write("pal.png", make_png(kW, kH, 8, 3, rows, plte, trns));
  const GreyImage image = read_image(path("pal.png"));
  EXPECT_EQ(image.alpha.size(), static_cast<std::size_t>(kW * kH));
  expect_pattern(read_bitmap(path("pal.png")));
}

TEST_F(ImageIoTest, PalettePngTwoBitWithoutTransparency) {
  // 2-bit indices, packed four to a byte: checks stb's unpacking through our path.
  std::vector<std::string> rows;
  for (int r = 0; r < kH; ++r) {
    std::string row((kW * 2 + 7) / 8, '\0');
    for (int c = 0; c < kW; ++c) {
      const int index = pattern(c, r) ? 2 : 1;
      row[static_cast<std::size_t>(c / 4)] |= static_cast<char>(index << (6 - 2 * (c % 4)));
    }
    rows.push_back(row);
  }
  const std::string plte("\x80\x80\x80\xf0\xf0\xf0\x10\x10\x10", 9);
  write("pal2.png", make_png(kW, kH, 2, 3, rows, plte));
  const GreyImage image = read_image(path("pal2.png"));
  EXPECT_TRUE(image.alpha.empty());
  expect_pattern(read_bitmap(path("pal2.png")));
}

TEST_F(ImageIoTest, SixteenBitPng) {
  std::vector<std::string> rows;
  for (int r = 0; r < kH; ++r) {
    std::string row;
    for (int c = 0; c < kW; ++c) {
      // Shape 0x1000 (16), background 0xF0F0 (240); background pixel (4,0) is mid grey
      // 0x8080 -> 128.
      const std::uint32_t v = (c == 4 && r == 0) ? 0x8080 : pattern(c, r) ? 0x1000 : 0xF0F0;
      row += static_cast<char>(v >> 8);
      row += static_cast<char>(v & 0xFF);
    }
    rows.push_back(row);
  }
  write("g16.png", make_png(kW, kH, 16, 0, rows));
  const GreyImage image = read_image(path("g16.png"));
  EXPECT_EQ(image.grey[0], 16);
  EXPECT_EQ(image.grey[4], 128);
  EXPECT_EQ(image.grey[static_cast<std::size_t>(kW)], 240);  // (0,1) is background
  ImageReadOptions options;
  options.threshold = 127;
  expect_pattern(read_bitmap(path("g16.png"), options));
}

TEST_F(ImageIoTest, Jpeg) {
  // JPEG is lossy: blocks aligned with its 8x8 grid and a clear contrast survive exactly.
  write("a.jpg", checker_jpeg());
  const GreyImage image = read_image(path("a.jpg"));
  EXPECT_TRUE(image.alpha.empty());
  const Bitmap b = read_bitmap(path("a.jpg"));
  const int n = 32;
  ASSERT_EQ(b.width(), n);
  ASSERT_EQ(b.height(), n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) EXPECT_EQ(b.get(c, r), (c / 8 + r / 8) % 2 == 1) << c << "," << r;
}

TEST_F(ImageIoTest, Bmp) {
  const auto px = pattern_pixels(3, {0, 0, 0}, {255, 255, 255});
  ASSERT_TRUE(stbi_write_bmp(path("a.bmp").c_str(), kW, kH, 3, px.data()));
  expect_pattern(read_bitmap(path("a.bmp")));
}

TEST_F(ImageIoTest, TgaRleAndUncompressed) {
  const auto px = pattern_pixels(4, {0, 0, 0, 255}, {255, 255, 255, 255});
  stbi_write_tga_with_rle = 1;
  ASSERT_TRUE(stbi_write_tga(path("rle.tga").c_str(), kW, kH, 4, px.data()));
  stbi_write_tga_with_rle = 0;
  ASSERT_TRUE(stbi_write_tga(path("raw.tga").c_str(), kW, kH, 4, px.data()));
  stbi_write_tga_with_rle = 1;
  expect_pattern(read_bitmap(path("rle.tga")));
  expect_pattern(read_bitmap(path("raw.tga")));
}

std::string pgm_raster(int maxval, int dark, int light, bool plain, int bytes = 1) {
  std::string s;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      const int v = pattern(c, r) ? dark : light;
      if (plain) {
        s += std::to_string(v) + (c + 1 == kW ? "\n" : " ");
      } else if (bytes == 2) {
        s += static_cast<char>(v >> 8);
        s += static_cast<char>(v & 0xFF);
      } else {
        s += static_cast<char>(v);
      }
    }
  (void)maxval;
  return s;
}

TEST_F(ImageIoTest, PgmRawPlainAndMaxval) {
  write("raw.pgm", "P5\n# a comment\n10 6\n255\n" + pgm_raster(255, 0, 255, false));
  expect_pattern(read_bitmap(path("raw.pgm")));
  write("plain.pgm", "P2\n10 6 255\n" + pgm_raster(255, 10, 200, true));
  expect_pattern(read_bitmap(path("plain.pgm")));
  // maxval 15: values are scaled, 12/15 -> 204, not left at 12 (which would be black).
  write("m15.pgm", "P5 10 6 15\n" + pgm_raster(15, 0, 12, false));
  const GreyImage image = read_image(path("m15.pgm"));
  EXPECT_EQ(image.grey[4], 204);  // (4,0) is background
  expect_pattern(read_bitmap(path("m15.pgm")));
}

TEST_F(ImageIoTest, SixteenBitPgm) {
  write("g16.pgm", "P5 10 6 65535\n" + pgm_raster(65535, 0x0101, 0xFEFE, false, 2));
  const GreyImage image = read_image(path("g16.pgm"));
  EXPECT_EQ(image.grey[0], 1);
  EXPECT_EQ(image.grey[4], 254);
  expect_pattern(read_bitmap(path("g16.pgm")));
  // maxval 1000 (two bytes per sample): 500 -> 128.
  write("m1000.pgm", std::string("P5 1 1 1000\n") + '\x01' + '\xF4');
  EXPECT_EQ(read_image(path("m1000.pgm")).grey[0], 128);
}

TEST_F(ImageIoTest, PpmRawAndPlain) {
  std::string raw, plain;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      const std::array<int, 3> rgb = pattern(c, r) ? std::array<int, 3>{30, 0, 60}
                                                    : std::array<int, 3>{255, 200, 220};
      for (int v : rgb) {
        raw += static_cast<char>(v);
        plain += std::to_string(v) + ' ';
      }
    }
  write("a.ppm", "P6 10 6 255\n" + raw);
  expect_pattern(read_bitmap(path("a.ppm")));
  write("p.ppm", "P3\n10 6\n255\n" + plain + "\n");
  expect_pattern(read_bitmap(path("p.ppm")));
}

TEST_F(ImageIoTest, PbmPlainAndRaw) {
  std::string p1 = "P1\n# made by hand\n10 6\n";
  std::string p4 = "P4\n10 6\n";
  for (int r = 0; r < kH; ++r) {
    unsigned char bytes[2] = {0, 0};
    for (int c = 0; c < kW; ++c) {
      // Plain PBM may run digits together; mix both spellings.
      p1 += pattern(c, r) ? "1" : "0";
      if (r % 2) p1 += ' ';
      if (pattern(c, r)) bytes[c / 8] |= static_cast<unsigned char>(0x80 >> (c % 8));
    }
    p1 += '\n';
    p4 += static_cast<char>(bytes[0]);
    p4 += static_cast<char>(bytes[1]);
  }
  write("plain.pbm", p1);
  write("raw.pbm", p4);
  expect_pattern(read_bitmap(path("plain.pbm")));
  expect_pattern(read_bitmap(path("raw.pbm")));
  EXPECT_EQ(read_image(path("raw.pbm")).grey[0], 0);  // 1 is black
}

TEST_F(ImageIoTest, OnePixelImages) {
  const unsigned char black = 0, white = 255;
  ASSERT_TRUE(stbi_write_png(path("b.png").c_str(), 1, 1, 1, &black, 1));
  ASSERT_TRUE(stbi_write_png(path("w.png").c_str(), 1, 1, 1, &white, 1));
  const Bitmap b = read_bitmap(path("b.png"));
  ASSERT_EQ(b.width(), 1);
  ASSERT_EQ(b.height(), 1);
  EXPECT_TRUE(b.get(0, 0));
  EXPECT_EQ(read_bitmap(path("w.png")).count(), 0u);
}

// ---------------------------------------------------------------------------------------------
// Thresholding

GreyImage grey_image(int w, int h, const std::function<int(int, int)>& value) {
  GreyImage image;
  image.width = w;
  image.height = h;
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) image.grey.push_back(static_cast<std::uint8_t>(value(c, r)));
  return image;
}

TEST(OtsuTest, BimodalHistogramSplitsBetweenModes) {
  // Two noisy modes around 40 and 190 with different weights.
  const GreyImage image = grey_image(100, 10, [](int c, int r) {
    const int noise = (c * 7 + r * 13) % 21 - 10;
    return (c < 30 ? 40 : 190) + noise;
  });
  const int t = otsu_threshold(image);
  EXPECT_GE(t, 50);
  EXPECT_LT(t, 180);
  const Bitmap b = threshold_image(image);
  EXPECT_EQ(b.count(), 300u);
}

TEST(OtsuTest, TwoLevelsCutInTheMiddleOfTheGap) {
  EXPECT_EQ(otsu_threshold(grey_image(4, 1, [](int c, int) { return c < 2 ? 0 : 255; })), 127);
  EXPECT_EQ(otsu_threshold(grey_image(4, 1, [](int c, int) { return c < 1 ? 100 : 110; })), 104);
}

TEST(OtsuTest, SingleLevelBlackIsShapeWhiteIsBackground) {
  const GreyImage black = grey_image(5, 5, [](int, int) { return 0; });
  const GreyImage white = grey_image(5, 5, [](int, int) { return 255; });
  EXPECT_EQ(threshold_image(black).count(), 25u);
  EXPECT_EQ(threshold_image(white).count(), 0u);
  ImageReadOptions invert;
  invert.invert = true;
  EXPECT_EQ(threshold_image(white, invert).count(), 25u);
}

TEST(OtsuTest, IgnoresTransparentPixels) {
  // Opaque pixels are 100 and 200; transparent ones at 0 must not pull the threshold down.
  GreyImage image = grey_image(30, 1, [](int c, int) { return c < 10 ? 0 : c < 20 ? 100 : 200; });
  image.alpha.assign(30, 255);
  for (int c = 0; c < 10; ++c) image.alpha[static_cast<std::size_t>(c)] = 0;
  const int t = otsu_threshold(image);
  EXPECT_GE(t, 100);
  EXPECT_LT(t, 200);
  EXPECT_EQ(threshold_image(image).count(), 10u);
}

TEST(ThresholdTest, ExplicitThresholdAndInvert) {
  const GreyImage image = grey_image(256, 1, [](int c, int) { return c; });
  ImageReadOptions options;
  options.threshold = 99;
  EXPECT_EQ(threshold_image(image, options).count(), 100u);  // 0..99 inclusive
  options.invert = true;
  const Bitmap inverted = threshold_image(image, options);
  EXPECT_EQ(inverted.count(), 156u);
  EXPECT_FALSE(inverted.get(99, 0));
  EXPECT_TRUE(inverted.get(100, 0));
  options.threshold = 256;
  EXPECT_THROW(threshold_image(image, options), InputError);
}

// ---------------------------------------------------------------------------------------------
// Bad input

TEST_F(ImageIoTest, MissingFile) {
  const std::string message = error_of(path("missing.png"));
  EXPECT_EQ(message, "cannot open '" + path("missing.png") + "': No such file or directory");
}

TEST_F(ImageIoTest, Directory) {
  fs::create_directory(path("folder.png"));
  EXPECT_NE(error_of(path("folder.png")).find("Is a directory"), std::string::npos);
}

TEST_F(ImageIoTest, EmptyFile) {
  write("empty.png", "");
  EXPECT_NE(error_of(path("empty.png")).find("empty"), std::string::npos);
}

TEST_F(ImageIoTest, TruncatedPng) {
  std::vector<unsigned char> px;
  for (int i = 0; i < 64 * 64; ++i) px.push_back(static_cast<unsigned char>((i * 37) % 256));
  ASSERT_TRUE(stbi_write_png(path("full.png").c_str(), 64, 64, 1, px.data(), 64));
  const std::string bytes = read(path("full.png"));
  write("half.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_NE(error_of(path("half.png")).find("not an image stb can decode (truncated or corrupt?)"),
            std::string::npos);
  // Even the missing IEND alone counts as truncation.
  write("noend.png", bytes.substr(0, bytes.size() - 12));
  error_of(path("noend.png"));
}

TEST_F(ImageIoTest, TextFileNamedPng) {
  write("notes.png", "These are my notes, not a picture.\n");
  EXPECT_EQ(error_of(path("notes.png")),
            "'" + path("notes.png") + "' is not an image stb can decode (truncated or corrupt?)");
}

TEST_F(ImageIoTest, TruncatedJpegBmpTgaPgmPbm) {
  // stb itself would fill the missing part of these with black (= shape) pixels.
  std::vector<unsigned char> px;
  for (int i = 0; i < 32 * 32 * 3; ++i) px.push_back(static_cast<unsigned char>((i * 37) % 256));
  write("a.jpg", checker_jpeg());
  ASSERT_TRUE(stbi_write_bmp(path("a.bmp").c_str(), 32, 32, 3, px.data()));
  stbi_write_tga_with_rle = 0;
  ASSERT_TRUE(stbi_write_tga(path("raw.tga").c_str(), 32, 32, 3, px.data()));
  stbi_write_tga_with_rle = 1;
  ASSERT_TRUE(stbi_write_tga(path("rle.tga").c_str(), 32, 32, 3, px.data()));
  for (const std::string name : {"a.jpg", "a.bmp", "raw.tga", "rle.tga"}) {
    const std::string bytes = read(path(name));
    ASSERT_NO_THROW(read_image(path(name))) << name;
    write("cut-" + name, bytes.substr(0, bytes.size() * 2 / 3));
    error_of(path("cut-" + name));
    write("short-" + name, bytes.substr(0, bytes.size() - 1));
    error_of(path("short-" + name));  // even one byte: the JPEG loses its EOI marker
  }
  write("cut.pgm", "P5 10 10 255\n" + std::string(99, '\x80'));
  EXPECT_NE(error_of(path("cut.pgm")).find("truncated"), std::string::npos);
  write("cut.pbm", "P4 10 10\n" + std::string(19, '\x80'));
  EXPECT_NE(error_of(path("cut.pbm")).find("truncated"), std::string::npos);
  write("cut1.pbm", "P1 3 3\n1 0 1\n0 1");
  EXPECT_NE(error_of(path("cut1.pbm")).find("truncated"), std::string::npos);
}

TEST_F(ImageIoTest, CorruptNetpbm) {
  write("bad1.pbm", "P1 2 2\n1 0\n2 1\n");
  error_of(path("bad1.pbm"));
  write("bad.pgm", "P5 2 2 70000\n....");
  EXPECT_NE(error_of(path("bad.pgm")).find("maxval"), std::string::npos);
  write("over.pgm", "P2 2 1 10\n3 11\n");
  error_of(path("over.pgm"));
  write("nosize.pgm", "P5 \n# only a comment\n");
  error_of(path("nosize.pgm"));
}

TEST_F(ImageIoTest, CorruptedFilesGiveInputErrorOrAnImage) {
  // Deterministic byte flips and cuts of a valid file of every format: each read either
  // succeeds with a consistent image or throws InputError; nothing else (run under the
  // sanitizers to catch memory errors too).
  const auto grey = pattern_pixels(1, {0}, {255});
  const auto rgba = pattern_pixels(4, {0, 0, 0, 255}, {255, 255, 255, 0});
  ASSERT_TRUE(stbi_write_png(path("a.png").c_str(), kW, kH, 4, rgba.data(), kW * 4));
  write("a.jpg", checker_jpeg());
  ASSERT_TRUE(stbi_write_bmp(path("a.bmp").c_str(), kW, kH, 4, rgba.data()));
  ASSERT_TRUE(stbi_write_tga(path("a.tga").c_str(), kW, kH, 1, grey.data()));
  write("a.pgm", "P5 10 6 255\n" + pgm_raster(255, 0, 255, false));
  write("b.pgm", "P2 10 6 255\n" + pgm_raster(255, 0, 255, true));
  write("a.pbm", "P1 2 2\n1 0\n0 1\n");
  write("b.pbm", std::string("P4 2 2\n\x80\x40", 9));
  std::uint32_t state = 12345;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  for (const std::string name :
       {"a.png", "a.jpg", "a.bmp", "a.tga", "a.pgm", "b.pgm", "a.pbm", "b.pbm"}) {
    const std::string original = read(path(name));
    // CSGFIT_FUZZ_TRIALS raises the count for a longer run under the sanitizers.
    const char* env = std::getenv("CSGFIT_FUZZ_TRIALS");
    const int trials = env != nullptr ? std::atoi(env) : 300;
    for (int trial = 0; trial < trials; ++trial) {
      std::string bytes = original;
      const int flips = 1 + static_cast<int>(next() % 4);
      for (int f = 0; f < flips; ++f) {
        bytes[next() % bytes.size()] = static_cast<char>(next() & 0xFF);
      }
      if (trial % 3 == 0) bytes.resize(next() % bytes.size() + 1);
      const std::string file = write("fuzz-" + name, bytes);
      try {
        const GreyImage image = read_image(file);
        ASSERT_GT(image.width, 0);
        ASSERT_GT(image.height, 0);
        ASSERT_EQ(image.grey.size(), static_cast<std::size_t>(image.width) * image.height);
        ASSERT_TRUE(image.alpha.empty() || image.alpha.size() == image.grey.size());
        threshold_image(image);
      } catch (const InputError& e) {
        ASSERT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      }
    }
  }
}

TEST_F(ImageIoTest, PngChunksAreChecked) {
  std::vector<std::string> rows;
  for (int r = 0; r < kH; ++r) {
    std::string row;
    for (int c = 0; c < kW; ++c) row += static_cast<char>(pattern(c, r) ? 0 : 255);
    rows.push_back(row);
  }
  const std::string png = make_png(kW, kH, 8, 0, rows);
  // An empty IDAT chunk is legal (stb would memcpy from a null pointer on it).
  const std::size_t after_ihdr = 8 + 12 + 13;
  write("empty-idat.png", png.substr(0, after_ihdr) + png_chunk("IDAT", "") + png.substr(after_ihdr));
  expect_pattern(read_bitmap(path("empty-idat.png")));
  // One flipped pixel byte: stb checks no CRC and would decode it as a grey pixel.
  std::string flipped = png;
  const std::size_t idat = flipped.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  flipped[idat + 4 + 2 + 5 + 3] ^= 0x40;  // inside the first stored block's pixel bytes
  write("flipped.png", flipped);
  error_of(path("flipped.png"));
}

TEST_F(ImageIoTest, JpegWithOverfullHuffmanTableIsRefused) {
  // Code counts adding up to more than 256 symbols overflow this stb version's tables.
  std::string jpeg = checker_jpeg();
  const std::size_t dht = jpeg.find("\xff\xc4");
  ASSERT_NE(dht, std::string::npos);
  for (std::size_t i = 0; i < 16; ++i) jpeg[dht + 5 + i] = '\x20';
  write("dht.jpg", jpeg);
  error_of(path("dht.jpg"));
}

TEST_F(ImageIoTest, RunLengthBmpGetsItsOwnMessage) {
  // 2 x 1, 8-bit palette, BI_RLE8: a header is enough to be told what is wrong.
  std::string bmp = "BM" + std::string(4, '\0') + std::string(4, '\0') + std::string("\x3e\0\0\0", 4);
  bmp += std::string("\x28\0\0\0", 4) + std::string("\x02\0\0\0\x01\0\0\0", 8);
  bmp += std::string("\x01\0\x08\0", 4) + std::string("\x01\0\0\0", 4) + std::string(20, '\0');
  bmp += std::string(8, '\0') + std::string("\x02\x00\x00\x01", 4);
  write("rle.bmp", bmp);
  EXPECT_NE(error_of(path("rle.bmp")).find("run-length compressed BMP"), std::string::npos);
}

TEST_F(ImageIoTest, ZeroByZeroImage) {
  write("zero.pgm", "P5 0 0 255\n");
  EXPECT_EQ(error_of(path("zero.pgm")), "'" + path("zero.pgm") + "' is 0 x 0 pixels");
  write("zero.png", make_png(0, 0, 8, 0, {}));
  EXPECT_NE(error_of(path("zero.png")).find("is 0 x 0 pixels"), std::string::npos);
  write("wide.pbm", "P4 5 0\n");
  EXPECT_NE(error_of(path("wide.pbm")).find("is 5 x 0 pixels"), std::string::npos);
}

TEST_F(ImageIoTest, HugeDeclaredSizeIsRefusedBeforeDecoding) {
  // Headers only: decoding would need 10 GB; the refusal must come from the header.
  write("huge.pgm", "P5 100000 100000 255\n");
  write("huge.png", make_png(100000, 100000, 8, 0, {}));
  write("big.png", make_png(20000, 20000, 8, 0, {}));
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NE(error_of(path("huge.pgm")).find("100000 x 100000 pixels, over the limit of 16777216"),
            std::string::npos);
  EXPECT_NE(error_of(path("huge.png")).find("over the limit"), std::string::npos);
  EXPECT_EQ(error_of(path("big.png")),
            "'" + path("big.png") +
                "' is 20000 x 20000 pixels, over the limit of 16777216 pixels (use --max-size to "
                "downsample)");
  // --max-size does not lift the bound on what is decoded at full size.
  ImageReadOptions options;
  options.max_size = 64;
  EXPECT_NE(error_of(path("huge.png"), options).find("even with --max-size"), std::string::npos);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
  // Within the decode bound the header passes but the missing pixel data is still caught.
  error_of(path("big.png"), options);
}

TEST_F(ImageIoTest, LimitsFromOptions) {
  const auto px = pattern_pixels(1, {0}, {255});
  ASSERT_TRUE(stbi_write_png(path("a.png").c_str(), kW, kH, 1, px.data(), kW));
  ImageReadOptions options;
  options.max_pixels = kW * kH - 1;
  EXPECT_NE(error_of(path("a.png"), options).find("over the limit of 59 pixels"),
            std::string::npos);
  options.max_size = 5;  // 10 x 6 -> 5 x 3
  const GreyImage image = read_image(path("a.png"), options);
  EXPECT_EQ(image.width, 5);
  EXPECT_EQ(image.height, 3);
  options.max_pixels = 10;  // even downsampled, 15 pixels are too many
  EXPECT_NE(error_of(path("a.png"), options).find("still over the limit"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Downsampling

TEST_F(ImageIoTest, MaxSizeDownsamplesByAreaAverage) {
  // 64 x 32: left half black, right half white -> 16 x 8 with the same halves.
  std::vector<unsigned char> px;
  for (int r = 0; r < 32; ++r)
    for (int c = 0; c < 64; ++c) px.push_back(c < 32 ? 0 : 255);
  ASSERT_TRUE(stbi_write_png(path("halves.png").c_str(), 64, 32, 1, px.data(), 64));
  ImageReadOptions options;
  options.max_size = 16;
  const GreyImage image = read_image(path("halves.png"), options);
  ASSERT_EQ(image.width, 16);
  ASSERT_EQ(image.height, 8);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 16; ++c)
      EXPECT_EQ(image.grey[static_cast<std::size_t>(r * 16 + c)], c < 8 ? 0 : 255);
  // Not larger than max_size: untouched.
  options.max_size = 64;
  EXPECT_EQ(read_image(path("halves.png"), options).width, 64);
}

TEST_F(ImageIoTest, DownsamplingSplitsPixelsByOverlap) {
  // 3 x 3 -> 2 x 2: the middle source row/column is shared half and half.
  write("3x3.pgm", std::string("P5 3 3 255\n") + std::string("\0\0\xff\0\0\xff\xff\xff\xff", 9));
  ImageReadOptions options;
  options.max_size = 2;
  const GreyImage image = read_image(path("3x3.pgm"), options);
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  EXPECT_EQ(image.grey, (std::vector<std::uint8_t>{0, 170, 170, 227}));
}

TEST_F(ImageIoTest, DownsamplingWeightsGreyByAlpha) {
  // 2 x 1 -> 1 x 1: opaque white next to transparent black stays white, half transparent.
  const unsigned char px[] = {255, 255, 0, 0};
  ASSERT_TRUE(stbi_write_png(path("ga.png").c_str(), 2, 1, 2, px, 4));
  ImageReadOptions options;
  options.max_size = 1;
  const GreyImage image = read_image(path("ga.png"), options);
  ASSERT_EQ(image.width, 1);
  EXPECT_EQ(image.grey[0], 255);
  EXPECT_EQ(image.alpha[0], 128);
}

// ---------------------------------------------------------------------------------------------
// Writing

std::vector<std::string> directory_entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST_F(ImageIoTest, WriteFileAtomic) {
  write_file_atomic(path("out.txt"), "first");
  EXPECT_EQ(read(path("out.txt")), "first");
  write_file_atomic(path("out.txt"), "second, longer");
  EXPECT_EQ(read(path("out.txt")), "second, longer");
  EXPECT_EQ(directory_entries(dir_), std::vector<std::string>{"out.txt"});
}

TEST_F(ImageIoTest, WriteFileAtomicFailureLeavesNoFile) {
  // A folder that does not exist: nothing can be created.
  try {
    write_file_atomic(path("nowhere/out.scad"), "x");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot write '" + path("nowhere/out.scad") + "': No such file or directory");
  }
  // The target is a directory: the temporary file is created next to it, then the rename
  // fails, and the temporary file must be gone.
  fs::create_directory(path("taken"));
  EXPECT_THROW(write_file_atomic(path("taken"), "x"), InputError);
  EXPECT_EQ(directory_entries(dir_), std::vector<std::string>{"taken"});
  EXPECT_TRUE(fs::is_empty(path("taken")));
}

TEST_F(ImageIoTest, PreviewColours) {
  // target: columns 0-1; result: columns 1-2; column 3 in neither.
  Bitmap target(4, 2), result(4, 2);
  for (int r = 0; r < 2; ++r) {
    target.set(0, r);
    target.set(1, r);
    result.set(1, r);
    result.set(2, r);
  }
  write_preview_png(path("preview.png"), target, result, 3);
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(path("preview.png").c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(w, 12);
  EXPECT_EQ(h, 6);
  auto colour = [&](int x, int y) {
    const unsigned char* p = px + (y * w + x) * 3;
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  EXPECT_EQ(colour(0, 0), (std::array<int, 3>{40, 90, 220}));   // uncovered: blue
  EXPECT_EQ(colour(5, 5), (std::array<int, 3>{64, 64, 64}));    // matched: dark grey
  EXPECT_EQ(colour(8, 2), (std::array<int, 3>{220, 40, 40}));   // excess: red
  EXPECT_EQ(colour(11, 0), (std::array<int, 3>{255, 255, 255}));  // background
  stbi_image_free(px);
  EXPECT_EQ(directory_entries(dir_), std::vector<std::string>{"preview.png"});
  EXPECT_THROW(write_preview_png(path("p2.png"), target, Bitmap(3, 2)), std::invalid_argument);
}

}  // namespace
}  // namespace csgfit
