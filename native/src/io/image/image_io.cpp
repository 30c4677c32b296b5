#include "csgfit/io/image.h"

#include "csgfit/io/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>
#include <random>
#include <stdexcept>

#include "csgfit/error.h"
#include "io/image/netpbm.h"

// stb is compiled here with static linkage, so another object that embeds stb cannot clash with
// it, and with only the formats we document (less code that parses untrusted bytes). Netpbm is
// read by image_netpbm.cpp instead of stb's PNM reader (see there why). The headers are included
// as <stb/...> so that they come from the system include path and our warning flags skip them.
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

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace csgfit {

namespace {

// With --max-size the image is decoded at full size before it is downsampled, so the decode
// needs its own bound: this many times max_pixels (1G pixels with the default limit).
constexpr long long kDecodeLimitFactor = 64;

// stb takes buffer lengths as int.
constexpr long long kMaxFileBytes = INT_MAX;

std::string quoted(const std::string& path) { return "'" + path + "'"; }

[[noreturn]] void fail(const std::string& message) { throw InputError(message); }

[[noreturn]] void fail_not_an_image(const std::string& path) {
  fail(quoted(path) + " is not an image stb can decode (truncated or corrupt?)");
}

long long saturating_mul(long long a, long long b) {
  if (a != 0 && b > LLONG_MAX / a) return LLONG_MAX;
  return a * b;
}

std::string size_text(long long width, long long height) {
  return std::to_string(width) + " x " + std::to_string(height) + " pixels";
}

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

std::vector<std::uint8_t> read_whole_file(const std::string& path) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) fail("cannot open " + quoted(path) + ": " + std::strerror(EISDIR));
  // Devices such as /dev/zero would never end; pipes are fine (reading from a shell pipeline).
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    fail("cannot open " + quoted(path) + ": not a regular file");
  }
  const std::string too_big = quoted(path) + " is larger than " +
                              std::to_string(kMaxFileBytes) + " bytes, too large to decode";
  if (S_ISREG(st.st_mode) && st.st_size > kMaxFileBytes) fail(too_big);

  std::vector<std::uint8_t> data;
  if (S_ISREG(st.st_mode)) data.reserve(static_cast<std::size_t>(st.st_size));
  std::uint8_t chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd.get(), chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("cannot read " + quoted(path) + ": " + std::strerror(errno));
    }
    if (n == 0) break;
    if (static_cast<long long>(data.size()) + n > kMaxFileBytes) fail(too_big);
    data.insert(data.end(), chunk, chunk + n);
  }
  return data;
}

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}
std::uint32_t le16(const std::uint8_t* p) { return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8); }
std::uint32_t le32(const std::uint8_t* p) {
  return le16(p) | (le16(p + 2) << 16);
}

enum class Format { kNetpbm, kPng, kJpeg, kBmp, kTga };

bool is_png(const std::vector<std::uint8_t>& d) {
  static const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return d.size() >= 8 && std::memcmp(d.data(), kSignature, 8) == 0;
}
bool is_jpeg(const std::vector<std::uint8_t>& d) {
  return d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF;
}
bool is_bmp(const std::vector<std::uint8_t>& d) {
  return d.size() >= 2 && d[0] == 'B' && d[1] == 'M';
}

// stb decodes a JPEG, BMP or TGA whose pixel data is cut short without complaint, filling the
// rest with zeros: black, i.e. shape. These checks catch that (and a few inputs known to crash
// this stb version) before decoding.

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

// Walks the PNG chunks: all must fit in the file, critical chunks (IHDR, PLTE, IDAT, IEND)
// must have a correct CRC (stb checks none, so a flipped bit could otherwise pass as pixels),
// and IEND must be there (a cut file). Empty IDAT chunks, which are legal but make this stb
// version memcpy from a null pointer, are dropped into `cleaned` (left empty when there are
// none, to avoid a copy).
bool png_is_complete(const std::vector<std::uint8_t>& d, std::vector<std::uint8_t>* cleaned) {
  const std::size_t n = d.size();
  std::size_t pos = 8;
  std::vector<std::pair<std::size_t, std::size_t>> empty_idat;  // [begin, end) to drop
  for (;;) {
    if (n - pos < 12) return false;
    const std::size_t length = be32(&d[pos]);
    if (length > n - pos - 12) return false;
    const std::uint8_t* type = &d[pos + 4];
    const bool critical = (type[0] & 0x20) == 0;
    if (critical && crc32(type, length + 4) != be32(&d[pos + 8 + length])) return false;
    const std::size_t next = pos + 12 + length;
    if (std::memcmp(type, "IEND", 4) == 0) break;
    if (length == 0 && std::memcmp(type, "IDAT", 4) == 0) empty_idat.emplace_back(pos, next);
    pos = next;
  }
  cleaned->clear();
  if (!empty_idat.empty()) {
    std::size_t from = 0;
    for (const auto& [begin, end] : empty_idat) {
      cleaned->insert(cleaned->end(), d.begin() + static_cast<std::ptrdiff_t>(from),
                      d.begin() + static_cast<std::ptrdiff_t>(begin));
      from = end;
    }
    cleaned->insert(cleaned->end(), d.begin() + static_cast<std::ptrdiff_t>(from), d.end());
  }
  return true;
}

// Huffman tables (DHT) whose code counts add up to more than 256 symbols make this stb version
// write past its tables (CVE-2021-37789), so they are refused here first.
bool jpeg_dht_is_valid(const std::uint8_t* segment, std::size_t length) {
  std::size_t pos = 0;
  while (pos < length) {
    if (length - pos < 17) return false;
    const std::uint8_t table = segment[pos];
    if ((table >> 4) > 1 || (table & 15) > 3) return false;
    std::size_t symbols = 0;
    for (std::size_t i = 1; i <= 16; ++i) symbols += segment[pos + i];
    if (symbols > 256 || length - pos - 17 < symbols) return false;
    pos += 17 + symbols;
  }
  return true;
}

enum class JpegCheck { kComplete, kTruncated, kUnsafe };

// A complete JPEG ends its last scan with an EOI marker. Segments are skipped by their length
// so that an EOI inside an embedded thumbnail (APP1) does not count.
JpegCheck check_jpeg(const std::vector<std::uint8_t>& d) {
  const std::size_t n = d.size();
  std::size_t pos = 2;
  for (;;) {
    while (pos < n && d[pos] != 0xFF) ++pos;  // entropy-coded data between markers
    while (pos < n && d[pos] == 0xFF) ++pos;  // fill bytes
    if (pos >= n) return JpegCheck::kTruncated;
    const std::uint8_t marker = d[pos++];
    if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;
    if (marker == 0xD9) return JpegCheck::kComplete;
    if (marker == 0xD8) return JpegCheck::kTruncated;
    if (pos + 2 > n) return JpegCheck::kTruncated;
    const std::size_t length = (std::size_t{d[pos]} << 8) | d[pos + 1];
    if (length < 2 || pos + length > n) return JpegCheck::kTruncated;
    if (marker == 0xC4 && !jpeg_dht_is_valid(&d[pos + 2], length - 2)) return JpegCheck::kUnsafe;
    pos += length;
  }
}

// Uncompressed BMP: the rows must fit in the file (stb does not read RLE BMPs).
bool bmp_is_complete(const std::vector<std::uint8_t>& d) {
  const std::size_t n = d.size();
  if (n < 18) return false;
  const std::uint32_t offset = le32(&d[10]);
  const std::uint32_t header_size = le32(&d[14]);
  long long width = 0;
  long long height = 0;
  std::uint32_t bpp = 0;
  std::uint32_t compression = 0;
  if (header_size == 12) {
    if (n < 26) return false;
    width = le16(&d[18]);
    height = le16(&d[20]);
    bpp = le16(&d[24]);
  } else {
    if (n < 34) return false;
    width = static_cast<std::int32_t>(le32(&d[18]));
    height = static_cast<std::int32_t>(le32(&d[22]));
    bpp = le16(&d[28]);
    compression = le32(&d[30]);
  }
  if (compression != 0 && compression != 3 && compression != 6) return true;  // stb decides
  const long long row_bytes = (std::llabs(width) * bpp + 31) / 32 * 4;
  const long long start = std::max<long long>(offset, 14LL + header_size);
  return start + saturating_mul(row_bytes, std::llabs(height)) <= static_cast<long long>(n);
}

// TGA, uncompressed or RLE: the pixel data must cover width * height pixels.
bool tga_is_complete(const std::vector<std::uint8_t>& d) {
  const std::size_t n = d.size();
  if (n < 18) return false;
  const std::uint32_t id_length = d[0];
  const std::uint32_t colormap_type = d[1];
  const std::uint32_t type = d[2];
  const std::uint32_t colormap_length = le16(&d[5]);
  const std::uint32_t colormap_bits = d[7];
  const long long width = le16(&d[12]);
  const long long height = le16(&d[14]);
  const long long pixel_bytes = (d[16] + 7) / 8;
  long long pos = 18 + id_length;
  if (colormap_type == 1) pos += colormap_length * ((colormap_bits + 7) / 8);
  const long long pixels = width * height;
  if (type >= 1 && type <= 3) return pos + pixels * pixel_bytes <= static_cast<long long>(n);
  if (type >= 9 && type <= 11) {
    long long remaining = pixels;
    while (remaining > 0) {
      if (pos >= static_cast<long long>(n)) return false;
      const std::uint8_t packet = d[static_cast<std::size_t>(pos++)];
      const long long count = (packet & 0x7F) + 1;
      pos += (packet & 0x80) ? pixel_bytes : count * pixel_bytes;
      remaining -= count;
    }
    return pos <= static_cast<long long>(n);
  }
  return true;  // stb decides
}

// Decoded pixels in one of stb's layouts: 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA)
// interleaved channels of 8 or 16 bits, row 0 at the top.
struct DecodedPixels {
  int width = 0;
  int height = 0;
  int channels = 0;
  bool sixteen_bit = false;
  const void* data = nullptr;

  bool has_alpha() const { return channels == 2 || channels == 4; }

  // Grey (luma) and alpha of one row, 8 bits each; `alpha` may be null.
  void convert_row(int row, std::uint8_t* grey, std::uint8_t* alpha) const {
    const std::size_t first = static_cast<std::size_t>(row) * static_cast<std::size_t>(width) *
                              static_cast<std::size_t>(channels);
    if (sixteen_bit) {
      convert(static_cast<const std::uint16_t*>(data) + first, grey, alpha,
              [](std::uint16_t v) { return static_cast<unsigned>((v * 255u + 32767u) / 65535u); });
    } else {
      convert(static_cast<const std::uint8_t*>(data) + first, grey, alpha,
              [](std::uint8_t v) { return static_cast<unsigned>(v); });
    }
  }

 private:
  template <typename T, typename To8>
  void convert(const T* in, std::uint8_t* grey, std::uint8_t* alpha, To8 to8) const {
    // Rec. 601 luma; exact for grey pixels (r = g = b).
    auto luma = [](unsigned r, unsigned g, unsigned b) {
      return static_cast<std::uint8_t>((299u * r + 587u * g + 114u * b + 500u) / 1000u);
    };
    for (int c = 0; c < width; ++c, in += channels) {
      std::uint8_t a = 255;
      switch (channels) {
        case 1:
          grey[c] = static_cast<std::uint8_t>(to8(in[0]));
          break;
        case 2:
          grey[c] = static_cast<std::uint8_t>(to8(in[0]));
          a = static_cast<std::uint8_t>(to8(in[1]));
          break;
        case 3:
          grey[c] = luma(to8(in[0]), to8(in[1]), to8(in[2]));
          break;
        default:
          grey[c] = luma(to8(in[0]), to8(in[1]), to8(in[2]));
          a = static_cast<std::uint8_t>(to8(in[3]));
          break;
      }
      if (alpha != nullptr) alpha[c] = a;
    }
  }
};

// Area-average downsampling, streamed one source row at a time so that only the small output
// is held in floating point. Overlaps are exact integers: a source pixel is `dst` units wide,
// an output pixel `src` units. Grey is averaged weighted by alpha so that the colour hidden
// under transparent pixels (often black) does not bleed into the edge.
class AreaDownsampler {
 public:
  AreaDownsampler(int src_width, int src_height, int dst_width, int dst_height, bool has_alpha)
      : src_width_(src_width),
        src_height_(src_height),
        dst_width_(dst_width),
        dst_height_(dst_height),
        has_alpha_(has_alpha),
        col_spans_(spans(src_width, dst_width)),
        row_spans_(spans(src_height, dst_height)),
        acc_grey_(static_cast<std::size_t>(dst_width) * dst_height, 0.0),
        row_grey_(static_cast<std::size_t>(dst_width)),
        row_grey_alpha_(static_cast<std::size_t>(dst_width)),
        row_alpha_(static_cast<std::size_t>(dst_width)) {
    if (has_alpha_) {
      acc_grey_alpha_.assign(acc_grey_.size(), 0.0);
      acc_alpha_.assign(acc_grey_.size(), 0.0);
    }
  }

  void add_row(int row, const std::uint8_t* grey, const std::uint8_t* alpha) {
    std::fill(row_grey_.begin(), row_grey_.end(), 0.0);
    std::fill(row_grey_alpha_.begin(), row_grey_alpha_.end(), 0.0);
    std::fill(row_alpha_.begin(), row_alpha_.end(), 0.0);
    for (int c = 0; c < src_width_; ++c) {
      const Span& s = col_spans_[static_cast<std::size_t>(c)];
      const double g = grey[c];
      const double a = has_alpha_ ? alpha[c] : 255.0;
      add_horizontal(s.first, static_cast<double>(s.weight_first), g, a);
      if (s.weight_second > 0) add_horizontal(s.first + 1, static_cast<double>(s.weight_second), g, a);
    }
    const Span& s = row_spans_[static_cast<std::size_t>(row)];
    add_vertical(s.first, static_cast<double>(s.weight_first));
    if (s.weight_second > 0) add_vertical(s.first + 1, static_cast<double>(s.weight_second));
  }

  GreyImage finish() const {
    GreyImage out;
    out.width = dst_width_;
    out.height = dst_height_;
    const std::size_t n = acc_grey_.size();
    out.grey.resize(n);
    if (has_alpha_) out.alpha.resize(n);
    const double total = static_cast<double>(src_width_) * static_cast<double>(src_height_);
    auto to8 = [](double v) {
      return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (has_alpha_) {
        out.alpha[i] = to8(acc_alpha_[i] / total);
        out.grey[i] = acc_alpha_[i] > 0 ? to8(acc_grey_alpha_[i] / acc_alpha_[i])
                                         : to8(acc_grey_[i] / total);
      } else {
        out.grey[i] = to8(acc_grey_[i] / total);
      }
    }
    return out;
  }

 private:
  // Source pixel i covers [i*dst, (i+1)*dst) and output pixel o covers [o*src, (o+1)*src);
  // with dst <= src a source pixel overlaps at most two output pixels.
  struct Span {
    int first = 0;
    long long weight_first = 0;
    long long weight_second = 0;
  };

  static std::vector<Span> spans(int src, int dst) {
    std::vector<Span> result(static_cast<std::size_t>(src));
    for (int i = 0; i < src; ++i) {
      const long long begin = static_cast<long long>(i) * dst;
      const long long end = begin + dst;
      const long long first = begin / src;
      const long long boundary = (first + 1) * src;
      Span& s = result[static_cast<std::size_t>(i)];
      s.first = static_cast<int>(first);
      if (end <= boundary) {
        s.weight_first = dst;
      } else {
        s.weight_first = boundary - begin;
        s.weight_second = end - boundary;
      }
    }
    return result;
  }

  void add_horizontal(int col, double weight, double grey, double alpha) {
    const std::size_t c = static_cast<std::size_t>(col);
    row_grey_[c] += weight * grey;
    row_grey_alpha_[c] += weight * grey * alpha;
    row_alpha_[c] += weight * alpha;
  }

  void add_vertical(int row, double weight) {
    const std::size_t base = static_cast<std::size_t>(row) * static_cast<std::size_t>(dst_width_);
    for (std::size_t c = 0; c < row_grey_.size(); ++c) {
      acc_grey_[base + c] += weight * row_grey_[c];
      if (has_alpha_) {
        acc_grey_alpha_[base + c] += weight * row_grey_alpha_[c];
        acc_alpha_[base + c] += weight * row_alpha_[c];
      }
    }
  }

  int src_width_;
  int src_height_;
  int dst_width_;
  int dst_height_;
  bool has_alpha_;
  std::vector<Span> col_spans_;
  std::vector<Span> row_spans_;
  std::vector<double> acc_grey_;
  std::vector<double> acc_grey_alpha_;
  std::vector<double> acc_alpha_;
  std::vector<double> row_grey_;
  std::vector<double> row_grey_alpha_;
  std::vector<double> row_alpha_;
};

GreyImage to_grey_image(const DecodedPixels& pixels, int out_width, int out_height) {
  std::vector<std::uint8_t> grey_row(static_cast<std::size_t>(pixels.width));
  std::vector<std::uint8_t> alpha_row(static_cast<std::size_t>(pixels.width));
  if (out_width == pixels.width && out_height == pixels.height) {
    GreyImage out;
    out.width = pixels.width;
    out.height = pixels.height;
    const std::size_t n = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
    out.grey.resize(n);
    if (pixels.has_alpha()) out.alpha.resize(n);
    for (int r = 0; r < pixels.height; ++r) {
      const std::size_t first = static_cast<std::size_t>(r) * static_cast<std::size_t>(out.width);
      pixels.convert_row(r, out.grey.data() + first,
                         pixels.has_alpha() ? out.alpha.data() + first : nullptr);
    }
    return out;
  }
  AreaDownsampler sampler(pixels.width, pixels.height, out_width, out_height, pixels.has_alpha());
  for (int r = 0; r < pixels.height; ++r) {
    pixels.convert_row(r, grey_row.data(), pixels.has_alpha() ? alpha_row.data() : nullptr);
    sampler.add_row(r, grey_row.data(), alpha_row.data());
  }
  return sampler.finish();
}

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

GreyImage read_image(const std::string& path, const ImageReadOptions& options) {
  const std::vector<std::uint8_t> file = read_whole_file(path);
  if (file.empty()) fail(quoted(path) + " is empty (0 bytes)");
  const int file_size = static_cast<int>(file.size());

  // Size from the header alone, so that the limits are checked before anything is allocated.
  Format format;
  JpegCheck jpeg_check = JpegCheck::kComplete;
  long long width = 0;
  long long height = 0;
  image_detail::NetpbmHeader netpbm;
  if (image_detail::looks_like_netpbm(file.data(), file.size())) {
    format = Format::kNetpbm;
    std::string reason;
    if (!image_detail::parse_netpbm_header(file.data(), file.size(), &netpbm, &reason)) {
      fail(quoted(path) + " is not a valid Netpbm image (" + reason + ")");
    }
    width = netpbm.width;
    height = netpbm.height;
  } else if (is_png(file) && file.size() >= 24 && std::memcmp(&file[12], "IHDR", 4) == 0) {
    // Read IHDR ourselves: stbi_info refuses large PNGs with a reason we could not report.
    format = Format::kPng;
    width = be32(&file[16]);
    height = be32(&file[20]);
  } else {
    format = is_png(file) ? Format::kPng
             : is_jpeg(file) ? Format::kJpeg
             : is_bmp(file)  ? Format::kBmp
                             : Format::kTga;
    // stb reads no run-length compressed BMP (ImageMagick writes them for grey images).
    if (format == Format::kBmp && file.size() >= 34 && le32(&file[14]) >= 40 &&
        (le32(&file[30]) == 1 || le32(&file[30]) == 2)) {
      fail(quoted(path) + " is a run-length compressed BMP, which is not supported (save it "
           "uncompressed or as PNG)");
    }
    // stbi_info already parses the JPEG tables, so the unsafe ones must be refused before.
    if (format == Format::kJpeg) jpeg_check = check_jpeg(file);
    if (jpeg_check == JpegCheck::kUnsafe) fail_not_an_image(path);
    int w = 0;
    int h = 0;
    int channels = 0;
    if (!stbi_info_from_memory(file.data(), file_size, &w, &h, &channels)) fail_not_an_image(path);
    width = w;
    height = h;
  }
  if (width <= 0 || height <= 0) fail(quoted(path) + " is " + size_text(width, height));

  // Output size: downsampled so that neither side exceeds max_size, keeping the aspect ratio.
  long long out_width = width;
  long long out_height = height;
  const long long max_size = options.max_size;
  if (max_size > 0 && (width > max_size || height > max_size)) {
    if (width >= height) {
      out_width = max_size;
      out_height = std::max(1LL, (saturating_mul(height, max_size) + width / 2) / width);
    } else {
      out_height = max_size;
      out_width = std::max(1LL, (saturating_mul(width, max_size) + height / 2) / height);
    }
  }
  const long long pixels = saturating_mul(width, height);
  const long long limit = options.max_pixels;
  if (out_width == width && out_height == height) {
    if (pixels > limit) {
      fail(quoted(path) + " is " + size_text(width, height) + ", over the limit of " +
           std::to_string(limit) + " pixels" + (max_size > 0 ? "" : " (use --max-size to downsample)"));
    }
  } else {
    const long long decode_limit = saturating_mul(limit, kDecodeLimitFactor);
    if (pixels > decode_limit) {
      fail(quoted(path) + " is " + size_text(width, height) + ", over the limit of " +
           std::to_string(decode_limit) + " pixels that can be decoded even with --max-size");
    }
    if (saturating_mul(out_width, out_height) > limit) {
      fail(quoted(path) + " downsampled to " + size_text(out_width, out_height) +
           " is still over the limit of " + std::to_string(limit) + " pixels");
    }
  }
  if (width > INT_MAX || height > INT_MAX) {  // only with an absurd --max-pixels
    fail(quoted(path) + " is " + size_text(width, height) + ", too large to decode");
  }

  if (format == Format::kNetpbm) {
    std::vector<std::uint8_t> raster;
    std::string reason;
    if (!image_detail::decode_netpbm(file.data(), file.size(), netpbm, &raster, &reason)) {
      fail(quoted(path) + " is not a valid Netpbm image (" + reason + ")");
    }
    DecodedPixels decoded;
    decoded.width = static_cast<int>(width);
    decoded.height = static_cast<int>(height);
    decoded.channels = netpbm.channels;
    decoded.data = raster.data();
    return to_grey_image(decoded, static_cast<int>(out_width), static_cast<int>(out_height));
  }

  std::vector<std::uint8_t> cleaned_png;
  if ((format == Format::kPng && !png_is_complete(file, &cleaned_png)) ||
      (format == Format::kJpeg && jpeg_check != JpegCheck::kComplete) ||
      (format == Format::kBmp && !bmp_is_complete(file)) ||
      (format == Format::kTga && !tga_is_complete(file))) {
    fail_not_an_image(path);
  }
  const std::uint8_t* bytes = cleaned_png.empty() ? file.data() : cleaned_png.data();
  const int byte_count = cleaned_png.empty() ? file_size : static_cast<int>(cleaned_png.size());

  DecodedPixels decoded;
  int w = 0;
  int h = 0;
  int channels = 0;
  std::unique_ptr<void, StbFree> buffer;
  if (stbi_is_16_bit_from_memory(bytes, byte_count)) {
    buffer.reset(stbi_load_16_from_memory(bytes, byte_count, &w, &h, &channels, 0));
    decoded.sixteen_bit = true;
  } else {
    buffer.reset(stbi_load_from_memory(bytes, byte_count, &w, &h, &channels, 0));
  }
  if (!buffer) {
    const char* reason = stbi_failure_reason();
    if (reason != nullptr &&
        (std::strcmp(reason, "too large") == 0 || std::strcmp(reason, "outofmem") == 0)) {
      fail(quoted(path) + " is " + size_text(width, height) + ", too large to decode");
    }
    fail_not_an_image(path);
  }
  if (w != width || h != height || channels < 1 || channels > 4) fail_not_an_image(path);
  decoded.width = w;
  decoded.height = h;
  decoded.channels = channels;
  decoded.data = buffer.get();
  return to_grey_image(decoded, static_cast<int>(out_width), static_cast<int>(out_height));
}

int otsu_threshold(const GreyImage& image) {
  // With a single grey level (or nothing opaque) there is nothing to separate; the middle of
  // the range makes a uniform dark image all shape and a uniform light one all background.
  constexpr int kUniformThreshold = 127;
  std::array<long long, 256> histogram{};
  const bool has_alpha = !image.alpha.empty();
  for (std::size_t i = 0; i < image.grey.size(); ++i) {
    if (has_alpha && image.alpha[i] < 128) continue;
    ++histogram[image.grey[i]];
  }
  long long total = 0;
  double total_sum = 0;
  for (int i = 0; i < 256; ++i) {
    total += histogram[static_cast<std::size_t>(i)];
    total_sum += static_cast<double>(i) * static_cast<double>(histogram[static_cast<std::size_t>(i)]);
  }
  if (total == 0) return kUniformThreshold;

  // Class 0 is "grey <= t". Maximise the between-class variance w0 * w1 * (mu0 - mu1)^2.
  double best = -1;
  int best_t = -1;
  long long n0 = 0;
  double sum0 = 0;
  for (int t = 0; t < 255; ++t) {
    n0 += histogram[static_cast<std::size_t>(t)];
    sum0 += static_cast<double>(t) * static_cast<double>(histogram[static_cast<std::size_t>(t)]);
    const long long n1 = total - n0;
    if (n0 == 0 || n1 == 0) continue;
    const double w0 = static_cast<double>(n0) / static_cast<double>(total);
    const double w1 = 1.0 - w0;
    const double mu0 = sum0 / static_cast<double>(n0);
    const double mu1 = (total_sum - sum0) / static_cast<double>(n1);
    const double variance = w0 * w1 * (mu0 - mu1) * (mu0 - mu1);
    if (variance > best * (1 + 1e-12)) {
      best = variance;
      best_t = t;
    }
  }
  if (best_t < 0) return kUniformThreshold;
  // Every t across the empty bins after best_t gives the same split; take the middle of that
  // gap, which is the most robust cut for clean two-level images (0/255 gives 127).
  int gap_end = best_t;
  while (gap_end + 1 < 255 && histogram[static_cast<std::size_t>(gap_end + 1)] == 0) ++gap_end;
  return (best_t + gap_end) / 2;
}

Bitmap threshold_image(const GreyImage& image, const ImageReadOptions& options) {
  const std::size_t n = static_cast<std::size_t>(std::max(image.width, 0)) *
                        static_cast<std::size_t>(std::max(image.height, 0));
  if (image.width < 0 || image.height < 0 || image.grey.size() != n ||
      (!image.alpha.empty() && image.alpha.size() != n)) {
    throw std::invalid_argument("threshold_image: grey/alpha sizes do not match the image size");
  }
  if (options.threshold > 255) {
    fail("threshold " + std::to_string(options.threshold) + " is outside 0..255");
  }
  const int threshold = options.threshold >= 0 ? options.threshold : otsu_threshold(image);
  Bitmap bitmap(image.width, image.height);
  const bool has_alpha = !image.alpha.empty();
  std::size_t i = 0;
  for (int r = 0; r < image.height; ++r) {
    for (int c = 0; c < image.width; ++c, ++i) {
      if (has_alpha && image.alpha[i] < 128) continue;
      const bool dark = image.grey[i] <= threshold;
      if (dark != options.invert) bitmap.set(c, r);
    }
  }
  return bitmap;
}

Bitmap read_bitmap(const std::string& path, const ImageReadOptions& options) {
  return threshold_image(read_image(path, options), options);
}

void write_preview_png(const std::string& path, const Bitmap& target, const Bitmap& result,
                       int scale) {
  if (target.width() != result.width() || target.height() != result.height()) {
    throw std::invalid_argument("write_preview_png: target and result differ in size");
  }
  if (target.empty()) throw std::invalid_argument("write_preview_png: empty bitmap");
  scale = std::max(scale, 1);
  const long long width = static_cast<long long>(target.width()) * scale;
  const long long height = static_cast<long long>(target.height()) * scale;
  if (width > INT_MAX / 3 || saturating_mul(width, height) > (1LL << 28)) {
    throw std::invalid_argument("write_preview_png: preview too large");
  }
  const int stride = static_cast<int>(width) * 3;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(stride) * static_cast<std::size_t>(height));
  for (int r = 0; r < target.height(); ++r) {
    for (int c = 0; c < target.width(); ++c) {
      const bool in_target = target.get(c, r);
      const bool in_result = result.get(c, r);
      std::array<std::uint8_t, 3> colour{255, 255, 255};
      if (in_target && in_result) colour = {64, 64, 64};
      else if (in_result) colour = {220, 40, 40};
      else if (in_target) colour = {40, 90, 220};
      for (int dy = 0; dy < scale; ++dy) {
        std::uint8_t* out = rgb.data() + static_cast<std::size_t>(r * scale + dy) * stride +
                            static_cast<std::size_t>(c) * scale * 3;
        for (int dx = 0; dx < scale; ++dx, out += 3) std::copy(colour.begin(), colour.end(), out);
      }
    }
  }
  std::string encoded;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &encoded, static_cast<int>(width), static_cast<int>(height),
                              3, rgb.data(), stride)) {
    fail("cannot write " + quoted(path) + ": PNG encoding failed");
  }
  write_file_atomic(path, encoded);
}

}  // namespace csgfit
