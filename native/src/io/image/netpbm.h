// Netpbm (PBM/PGM/PPM, plain and raw) reader used by read_image.cpp.
//
// Our own reader rather than stb's: stb reads only P5/P6, ignores maxval (a PGM with maxval 15
// would come out almost black) and does not notice a truncated raster (it returns uninitialised
// pixels), while PBM (P1/P4) is not supported at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace csgfit::image_detail {

/// Header of a Netpbm file.
struct NetpbmHeader {
  char kind = 0;              ///< '1'..'6' (P1..P6)
  long long width = 0;        ///< as declared (clamped to a large value while parsing)
  long long height = 0;
  int maxval = 1;             ///< 1 for PBM
  int channels = 1;           ///< 3 for PPM, 1 otherwise
  std::size_t raster_offset = 0;  ///< first byte after the header
};

/// True when the data starts like a Netpbm file ("P1".."P6" followed by whitespace or '#').
bool looks_like_netpbm(const std::uint8_t* data, std::size_t size);

/// Parses the header. Returns false with a short reason ("bad header", ...) on a malformed one.
bool parse_netpbm_header(const std::uint8_t* data, std::size_t size, NetpbmHeader* header,
                         std::string* reason);

/// Decodes the raster to 8 bits per channel, `channels` per pixel, row 0 at the top, values
/// scaled from 0..maxval to 0..255 (PBM: 1 = black = 0, 0 = white = 255). Returns false with a
/// short reason when the raster is truncated or holds invalid values. The caller has checked
/// the size limits already.
bool decode_netpbm(const std::uint8_t* data, std::size_t size, const NetpbmHeader& header,
                   std::vector<std::uint8_t>* pixels, std::string* reason);

}  // namespace csgfit::image_detail
