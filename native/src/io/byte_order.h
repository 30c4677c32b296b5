// Fixed-size numbers in the binary formats (STL, PLY, .npy, PNG, BMP, TGA), read byte by byte
// so that neither alignment nor the host's byte order matter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace csgfit::io_detail {

/// The bytes of a whole file as read_whole_file returns it.
inline const unsigned char* bytes_of(const std::string& d) {
  return reinterpret_cast<const unsigned char*>(d.data());
}

inline std::uint32_t le16(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8);
}

inline std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

inline std::uint32_t be32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

/// A value of type T (integer or IEEE float) stored at p, in big- or little-endian order.
/// Assumes a little-endian host.
template <typename T>
T load(const unsigned char* p, bool big_endian) {
  unsigned char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = big_endian ? p[sizeof(T) - 1 - i] : p[i];
  T value;
  std::memcpy(&value, b, sizeof value);
  return value;
}

}  // namespace csgfit::io_detail
