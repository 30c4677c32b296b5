#include "io/image/netpbm.h"

#include <algorithm>

namespace csgfit::image_detail {

namespace {

// Declared sizes are clamped here while parsing so that absurd headers cannot overflow; the
// caller refuses anything this large long before it would allocate.
constexpr long long kNumberCap = 1LL << 40;

bool is_space(std::uint8_t c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

bool is_digit(std::uint8_t c) { return c >= '0' && c <= '9'; }

// Skips whitespace and '#' comments (which run to the end of the line).
void skip_space_and_comments(const std::uint8_t* data, std::size_t size, std::size_t* pos) {
  while (*pos < size) {
    if (is_space(data[*pos])) {
      ++*pos;
    } else if (data[*pos] == '#') {
      while (*pos < size && data[*pos] != '\n' && data[*pos] != '\r') ++*pos;
    } else {
      break;
    }
  }
}

// Reads an unsigned decimal number at *pos (no sign, at least one digit).
bool read_number(const std::uint8_t* data, std::size_t size, std::size_t* pos, long long* value) {
  if (*pos >= size || !is_digit(data[*pos])) return false;
  long long v = 0;
  while (*pos < size && is_digit(data[*pos])) {
    if (v < kNumberCap) v = v * 10 + (data[*pos] - '0');
    ++*pos;
  }
  *value = v < kNumberCap ? v : kNumberCap;
  return true;
}

std::uint8_t scale_to_8bit(long long v, int maxval) {
  return static_cast<std::uint8_t>((v * 255 + maxval / 2) / maxval);
}

}  // namespace

bool looks_like_netpbm(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == 'P' && data[1] >= '1' && data[1] <= '6' &&
         (is_space(data[2]) || data[2] == '#');
}

bool parse_netpbm_header(const std::uint8_t* data, std::size_t size, NetpbmHeader* header,
                         std::string* reason) {
  if (!looks_like_netpbm(data, size)) {
    *reason = "not a Netpbm file";
    return false;
  }
  NetpbmHeader h;
  h.kind = static_cast<char>(data[1]);
  const bool bitmap = h.kind == '1' || h.kind == '4';
  h.channels = (h.kind == '3' || h.kind == '6') ? 3 : 1;
  std::size_t pos = 2;
  long long maxval = 1;
  skip_space_and_comments(data, size, &pos);
  if (!read_number(data, size, &pos, &h.width)) {
    *reason = "bad Netpbm header (width)";
    return false;
  }
  skip_space_and_comments(data, size, &pos);
  if (!read_number(data, size, &pos, &h.height)) {
    *reason = "bad Netpbm header (height)";
    return false;
  }
  if (!bitmap) {
    skip_space_and_comments(data, size, &pos);
    if (!read_number(data, size, &pos, &maxval)) {
      *reason = "bad Netpbm header (maxval)";
      return false;
    }
    if (maxval < 1 || maxval > 65535) {
      *reason = "bad Netpbm maxval " + std::to_string(maxval) + " (must be 1..65535)";
      return false;
    }
  }
  h.maxval = static_cast<int>(maxval);
  // Exactly one whitespace character separates the header from the raster. An empty raster
  // (a 0 x 0 image) may end the file right after the last number.
  if (pos < size) {
    if (!is_space(data[pos])) {
      *reason = "bad Netpbm header";
      return false;
    }
    ++pos;
  }
  h.raster_offset = pos;
  *header = h;
  return true;
}

namespace {

// Raw PBM: rows of ceil(w/8) bytes, most significant bit first, 1 = black.
bool decode_raw_pbm(const std::uint8_t* data, std::size_t available, std::size_t width,
                    std::size_t height, std::uint8_t* out, std::string* reason) {
  const std::size_t row_bytes = (width + 7) / 8;
  if (available / (row_bytes ? row_bytes : 1) < height) {
    *reason = "truncated";
    return false;
  }
  for (std::size_t r = 0; r < height; ++r) {
    const std::uint8_t* row = data + r * row_bytes;
    for (std::size_t c = 0; c < width; ++c) {
      const bool black = (row[c >> 3] >> (7 - (c & 7))) & 1u;
      out[r * width + c] = black ? 0 : 255;
    }
  }
  return true;
}

// Raw PGM/PPM: one or two bytes (big endian) per sample.
bool decode_raw_samples(const std::uint8_t* in, std::size_t available, std::size_t samples,
                        int maxval, std::uint8_t* out, std::string* reason) {
  const std::size_t bytes_per_sample = maxval < 256 ? 1 : 2;
  if (available / bytes_per_sample < samples) {
    *reason = "truncated";
    return false;
  }
  for (std::size_t i = 0; i < samples; ++i) {
    const long long v = bytes_per_sample == 1 ? in[i] : (in[2 * i] << 8) | in[2 * i + 1];
    if (v > maxval) {
      *reason = "sample value over maxval";
      return false;
    }
    out[i] = scale_to_8bit(v, maxval);
  }
  return true;
}

// Plain PBM ('0'/'1' characters, whitespace optional between them) or plain PGM/PPM (decimal
// samples separated by whitespace), from pos.
bool decode_plain(const std::uint8_t* data, std::size_t size, std::size_t pos,
                  const NetpbmHeader& header, std::size_t samples, std::uint8_t* out,
                  std::string* reason) {
  for (std::size_t i = 0; i < samples; ++i) {
    skip_space_and_comments(data, size, &pos);
    if (pos >= size) {
      *reason = "truncated";
      return false;
    }
    if (header.kind == '1') {
      const std::uint8_t c = data[pos++];
      if (c != '0' && c != '1') {
        *reason = "invalid character in plain PBM raster";
        return false;
      }
      out[i] = c == '1' ? 0 : 255;
      continue;
    }
    long long v = 0;
    if (!read_number(data, size, &pos, &v)) {
      *reason = "invalid character in plain Netpbm raster";
      return false;
    }
    if (v > header.maxval) {
      *reason = "sample value over maxval";
      return false;
    }
    out[i] = scale_to_8bit(v, header.maxval);
  }
  return true;
}

}  // namespace

bool decode_netpbm(const std::uint8_t* data, std::size_t size, const NetpbmHeader& header,
                   std::vector<std::uint8_t>* pixels, std::string* reason) {
  const std::size_t width = static_cast<std::size_t>(header.width);
  const std::size_t height = static_cast<std::size_t>(header.height);
  const std::size_t samples = width * height * static_cast<std::size_t>(header.channels);
  pixels->assign(samples, 0);
  const std::size_t pos = header.raster_offset;
  const std::size_t available = pos <= size ? size - pos : 0;
  const std::uint8_t* raster = data + std::min(pos, size);
  std::uint8_t* out = pixels->data();
  switch (header.kind) {
    case '4':
      return decode_raw_pbm(raster, available, width, height, out, reason);
    case '5':
    case '6':
      return decode_raw_samples(raster, available, samples, header.maxval, out, reason);
    case '1':
    case '2':
    case '3':
      return decode_plain(data, size, pos, header, samples, out, reason);
    default:
      *reason = "not a Netpbm file";
      return false;
  }
}

}  // namespace csgfit::image_detail
