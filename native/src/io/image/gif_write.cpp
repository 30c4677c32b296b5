// Animated GIF output for morphs: black-on-white frames, LZW-coded as GIF89a asks (stb writes
// no GIF, and two colours need no quantiser), looping forever, written atomically.
#include <array>
#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "csgfit/io/files.h"
#include "csgfit/io/image.h"

namespace csgfit {

namespace {

constexpr int kMinCodeSize = 2;  // GIF's smallest: a four-entry colour table
constexpr int kClear = 1 << kMinCodeSize, kEnd = kClear + 1, kMaxCode = 4095;

// Codes packed least significant bit first into 255-byte sub-blocks.
class CodeStream {
 public:
  explicit CodeStream(std::string& out) : out_(out) {}
  void put(int code, int bits) {
    acc_ |= static_cast<std::uint32_t>(code) << count_;
    count_ += bits;
    while (count_ >= 8) byte(acc_ & 0xff), acc_ >>= 8, count_ -= 8;
  }
  void finish() {
    if (count_ > 0) byte(acc_ & 0xff);
    flush();
    out_.push_back('\0');
  }

 private:
  void byte(std::uint32_t b) {
    block_.push_back(static_cast<char>(b));
    if (block_.size() == 255) flush();
  }
  void flush() {
    if (block_.empty()) return;
    out_.push_back(static_cast<char>(block_.size()));
    out_ += block_;
    block_.clear();
  }
  std::string& out_;
  std::string block_;
  std::uint32_t acc_ = 0;
  int count_ = 0;
};

// LZW over colour indices 0 and 1; the dictionary is a trie of (code, index) -> code.
void lzw(const std::vector<std::uint8_t>& pixels, std::string& out) {
  out.push_back(static_cast<char>(kMinCodeSize));
  CodeStream codes(out);
  std::vector<std::array<int, 2>> next(kMaxCode + 1);
  auto reset = [&] {
    for (auto& n : next) n = {0, 0};
  };
  reset();
  int size = kMinCodeSize + 1, last = kEnd;
  codes.put(kClear, size);
  int current = pixels[0];
  for (std::size_t i = 1; i < pixels.size(); ++i) {
    const int p = pixels[i];
    if (next[current][p] != 0) {
      current = next[current][p];
      continue;
    }
    codes.put(current, size);
    next[current][p] = ++last;
    if (last >= (1 << size)) ++size;
    if (last == kMaxCode) {
      codes.put(kClear, size);
      reset();
      size = kMinCodeSize + 1;
      last = kEnd;
    }
    current = p;
  }
  codes.put(current, size);
  codes.put(kClear, size);
  codes.put(kEnd, kMinCodeSize + 1);
  codes.finish();
}

void put16(std::string& out, int v) {
  out.push_back(static_cast<char>(v & 0xff));
  out.push_back(static_cast<char>((v >> 8) & 0xff));
}

// One frame's colour indices, scaled (a bitmap's row 0 is the top row, as in GIF).
std::vector<std::uint8_t> indices(const Bitmap& frame, int scale) {
  const int w = frame.width() * scale, h = frame.height() * scale;
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      px[static_cast<std::size_t>(y) * w + x] = frame.get(x / scale, y / scale) ? 1 : 0;
  return px;
}

}  // namespace

void write_bitmaps_gif(const std::string& path, const std::vector<Bitmap>& frames, int scale,
                       int delay_cs) {
  if (frames.empty()) throw std::invalid_argument("write_bitmaps_gif: no frames");
  scale = std::max(scale, 1);
  const long long w = static_cast<long long>(frames[0].width()) * scale;
  const long long h = static_cast<long long>(frames[0].height()) * scale;
  if (w < 1 || h < 1 || w > 65535 || h > 65535 || w * h * static_cast<long long>(frames.size()) > (1LL << 30))
    throw std::invalid_argument("write_bitmaps_gif: frames too large");
  std::string out = "GIF89a";
  put16(out, static_cast<int>(w));
  put16(out, static_cast<int>(h));
  out += std::string("\x91\x00\x00", 3);  // global table of 4 colours, background 0
  out += std::string("\xff\xff\xff\x00\x00\x00\x80\x80\x80\xc0\xc0\xc0", 12);
  out += std::string("\x21\xff\x0bNETSCAPE2.0\x03\x01\x00\x00\x00", 19);  // loop forever
  for (const Bitmap& f : frames) {
    if (f.width() != frames[0].width() || f.height() != frames[0].height())
      throw std::invalid_argument("write_bitmaps_gif: frames differ in size");
    out += std::string("\x21\xf9\x04\x00", 4);
    put16(out, delay_cs);
    out += std::string("\x00\x00", 2);
    out.push_back('\x2c');
    put16(out, 0);
    put16(out, 0);
    put16(out, static_cast<int>(w));
    put16(out, static_cast<int>(h));
    out.push_back('\0');
    lzw(indices(f, scale), out);
  }
  out.push_back('\x3b');
  write_file_atomic(path, out);
}

}  // namespace csgfit
