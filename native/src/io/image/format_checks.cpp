#include "io/image/format_checks.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "io/byte_order.h"

namespace csgfit::image_detail {

using io_detail::be32;
using io_detail::bytes_of;
using io_detail::le16;
using io_detail::le32;

namespace {

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

// Huffman tables (DHT) whose code counts add up to more than 256 symbols make this stb version
// write past its tables (CVE-2021-37789), so they are refused here first.
// `defined` gets a bit per table the segment defines: DC tables 0-3, AC tables 4-7.
bool jpeg_dht_is_valid(const std::uint8_t* segment, std::size_t length, unsigned* defined) {
  std::size_t pos = 0;
  while (pos < length) {
    if (length - pos < 17) return false;
    const std::uint8_t table = segment[pos];
    if ((table >> 4) > 1 || (table & 15) > 3) return false;
    *defined |= 1u << ((table >> 4) * 4 + (table & 15));
    std::size_t symbols = 0;
    for (std::size_t i = 1; i <= 16; ++i) symbols += segment[pos + i];
    if (symbols > 256 || length - pos - 17 < symbols) return false;
    pos += 17 + symbols;
  }
  return true;
}

// The Huffman tables a scan (SOS segment) decodes with must have been defined before it: stb
// reads a table never defined from uninitialised memory, and indexes out of its arrays with it
// (found by fuzz_jpeg). Progressive scans use only the DC (first DC scans) or the AC tables.
bool jpeg_scan_tables_defined(const std::uint8_t* segment, std::size_t length, bool progressive,
                              unsigned defined) {
  if (length < 1) return false;
  const std::size_t components = segment[0];
  if (length < 1 + 2 * components + 3) return false;
  const std::uint8_t start = segment[1 + 2 * components];
  const std::uint8_t refine = segment[3 + 2 * components] >> 4;
  const bool dc = !progressive || (start == 0 && refine == 0);
  const bool ac = !progressive || start > 0;
  for (std::size_t i = 0; i < components; ++i) {
    const unsigned tables = segment[2 + 2 * i];
    if ((tables >> 4) > 3 || (tables & 15) > 3) return false;
    if (dc && !((defined >> (tables >> 4)) & 1u)) return false;
    if (ac && !((defined >> (4 + (tables & 15))) & 1u)) return false;
  }
  return true;
}

}  // namespace

bool is_png(const std::string& d) {
  static const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return d.size() >= 8 && std::memcmp(d.data(), kSignature, 8) == 0;
}

// As stb recognises one (its SOI marker may have fill bytes: FF FF D8), so that stb never
// parses a JPEG that check_jpeg has not seen.
bool is_jpeg(const std::string& d) {
  const std::uint8_t* u = bytes_of(d);
  std::size_t i = 1;
  while (i < d.size() && u[i] == 0xFF) ++i;
  return d.size() >= 2 && u[0] == 0xFF && i < d.size() && u[i] == 0xD8;
}

bool is_bmp(const std::string& d) { return d.size() >= 2 && d[0] == 'B' && d[1] == 'M'; }

bool png_is_complete(const std::string& d, std::vector<std::uint8_t>* cleaned) {
  const std::uint8_t* u = bytes_of(d);
  const std::size_t n = d.size();
  std::size_t pos = 8;
  std::vector<std::pair<std::size_t, std::size_t>> empty_idat;  // [begin, end) to drop
  for (;;) {
    if (n - pos < 12) return false;
    const std::size_t length = be32(u + pos);
    if (length > n - pos - 12) return false;
    const std::uint8_t* type = u + pos + 4;
    const bool critical = (type[0] & 0x20) == 0;
    if (critical && crc32(type, length + 4) != be32(u + pos + 8 + length)) return false;
    const std::size_t next = pos + 12 + length;
    if (std::memcmp(type, "IEND", 4) == 0) break;
    if (length == 0 && std::memcmp(type, "IDAT", 4) == 0) empty_idat.emplace_back(pos, next);
    pos = next;
  }
  cleaned->clear();
  if (!empty_idat.empty()) {
    std::size_t from = 0;
    for (const auto& [begin, end] : empty_idat) {
      cleaned->insert(cleaned->end(), u + from, u + begin);
      from = end;
    }
    cleaned->insert(cleaned->end(), u + from, u + n);
  }
  return true;
}

// Segments are skipped by their length so that an EOI inside an embedded thumbnail (APP1) does
// not count.
JpegCheck check_jpeg(const std::string& d) {
  const std::uint8_t* u = bytes_of(d);
  const std::size_t n = d.size();
  std::size_t pos = 2;
  unsigned tables = 0;  // the Huffman tables defined so far (jpeg_dht_is_valid)
  bool progressive = false;
  for (;;) {
    while (pos < n && u[pos] != 0xFF) ++pos;  // entropy-coded data between markers
    while (pos < n && u[pos] == 0xFF) ++pos;  // fill bytes
    if (pos >= n) return JpegCheck::kTruncated;
    const std::uint8_t marker = u[pos++];
    if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;
    if (marker == 0xD9) return JpegCheck::kComplete;
    if (marker == 0xD8) return JpegCheck::kTruncated;
    if (pos + 2 > n) return JpegCheck::kTruncated;
    const std::size_t length = (std::size_t{u[pos]} << 8) | u[pos + 1];
    if (length < 2 || pos + length > n) return JpegCheck::kTruncated;
    if (marker == 0xC4 && !jpeg_dht_is_valid(u + pos + 2, length - 2, &tables)) {
      return JpegCheck::kUnsafe;
    }
    if (marker == 0xC2) progressive = true;
    if (marker == 0xDA && !jpeg_scan_tables_defined(u + pos + 2, length - 2, progressive, tables)) {
      return JpegCheck::kUnsafe;
    }
    pos += length;
  }
}

bool bmp_is_complete(const std::string& d) {
  const std::uint8_t* u = bytes_of(d);
  const std::size_t n = d.size();
  if (n < 18) return false;
  const std::uint32_t offset = le32(u + 10);
  const std::uint32_t header_size = le32(u + 14);
  long long width = 0;
  long long height = 0;
  std::uint32_t bpp = 0;
  std::uint32_t compression = 0;
  if (header_size == 12) {
    if (n < 26) return false;
    width = le16(u + 18);
    height = le16(u + 20);
    bpp = le16(u + 24);
  } else {
    if (n < 34) return false;
    width = static_cast<std::int32_t>(le32(u + 18));
    height = static_cast<std::int32_t>(le32(u + 22));
    bpp = le16(u + 28);
    compression = le32(u + 30);
  }
  if (compression != 0 && compression != 3 && compression != 6) return true;  // stb decides
  const long long row_bytes = (std::llabs(width) * bpp + 31) / 32 * 4;
  const long long start = std::max<long long>(offset, 14LL + header_size);
  return start + saturating_mul(row_bytes, std::llabs(height)) <= static_cast<long long>(n);
}

bool tga_is_complete(const std::string& d) {
  const std::uint8_t* u = bytes_of(d);
  const std::size_t n = d.size();
  if (n < 18) return false;
  const std::uint32_t id_length = u[0];
  const std::uint32_t colormap_type = u[1];
  const std::uint32_t type = u[2];
  const std::uint32_t colormap_length = le16(u + 5);
  const std::uint32_t colormap_bits = u[7];
  const long long width = le16(u + 12);
  const long long height = le16(u + 14);
  const long long pixel_bytes = (u[16] + 7) / 8;
  long long pos = 18 + id_length;
  if (colormap_type == 1) pos += colormap_length * ((colormap_bits + 7) / 8);
  const long long pixels = width * height;
  if (type >= 1 && type <= 3) return pos + pixels * pixel_bytes <= static_cast<long long>(n);
  if (type >= 9 && type <= 11) {
    long long remaining = pixels;
    while (remaining > 0) {
      if (pos >= static_cast<long long>(n)) return false;
      const std::uint8_t packet = u[static_cast<std::size_t>(pos++)];
      const long long count = (packet & 0x7F) + 1;
      pos += (packet & 0x80) ? pixel_bytes : count * pixel_bytes;
      remaining -= count;
    }
    return pos <= static_cast<long long>(n);
  }
  return true;  // stb decides
}

}  // namespace csgfit::image_detail
