// PNGs written by hand (stored deflate blocks), for the variants stb_image_write cannot
// produce (palette, 16 bit) and for bytes the readers under test must not have made.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace csgfit::testing {

inline std::string be32(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}
inline std::string le16(std::uint32_t v) {
  return {static_cast<char>(v), static_cast<char>(v >> 8)};
}

inline std::uint32_t crc32(const std::string& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : data) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

inline std::string png_chunk(const std::string& type, const std::string& data) {
  return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32(type + data));
}

// zlib stream made of stored (uncompressed) deflate blocks.
inline std::string zlib_stored(const std::string& raw) {
  std::string out = "\x78\x01";
  std::size_t pos = 0;
  do {
    const std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
    const bool final = pos + len == raw.size();
    out += static_cast<char>(final ? 1 : 0);
    out += le16(static_cast<std::uint32_t>(len));
    out += le16(static_cast<std::uint32_t>(~len & 0xFFFF));
    out += raw.substr(pos, len);
    pos += len;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  return out + be32((b << 16) | a);
}

// A PNG written by hand, for the variants stb_image_write cannot produce (palette, 16 bit).
// `rows` holds the scanlines without filter bytes.
inline std::string make_png(std::uint32_t w, std::uint32_t h, int depth, int color_type,
                     const std::vector<std::string>& rows, const std::string& plte = "",
                     const std::string& trns = "") {
  std::string raw;
  for (const std::string& row : rows) raw += '\0' + row;
  std::string ihdr = be32(w) + be32(h);
  ihdr += static_cast<char>(depth);
  ihdr += static_cast<char>(color_type);
  ihdr += std::string(3, '\0');
  std::string png = "\x89PNG\r\n\x1a\n" + png_chunk("IHDR", ihdr);
  if (!plte.empty()) png += png_chunk("PLTE", plte);
  if (!trns.empty()) png += png_chunk("tRNS", trns);
  if (!rows.empty()) png += png_chunk("IDAT", zlib_stored(raw));
  return png + png_chunk("IEND", "");
}

}  // namespace csgfit::testing
