#include "io/npy_array.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/sniff.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

[[noreturn]] void fail_npy(const std::string& path, const char* noun, const std::string& what) {
  fail(quoted(path) + " is not a usable NumPy " + noun + ": " + what);
}

// The header dict's text, after the signature and version; *data_start gets where the array
// begins.
std::string header_dict(const std::string& path, const std::string& d, const char* noun,
                        std::size_t* data_start) {
  if (!starts_with(d, "\x93NUMPY")) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a NumPy .npy array");
    fail(quoted(path) + " is not a NumPy .npy file (no \\x93NUMPY signature)");
  }
  if (d.size() < 10) fail(quoted(path) + " is truncated (NumPy header cut short)");
  const unsigned char* u = bytes_of(d);
  const int major = u[6];
  std::size_t header_len, header_start;
  if (major == 1) {
    header_len = le16(u + 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (d.size() < 12) fail(quoted(path) + " is truncated (NumPy header cut short)");
    header_len = le32(u + 8);
    header_start = 12;
  } else {
    fail_npy(path, noun, "unknown .npy version " + std::to_string(major));
  }
  if (header_len > d.size() - header_start) {
    fail(quoted(path) + " is truncated (NumPy header cut short)");
  }
  *data_start = header_start + header_len;
  return d.substr(header_start, header_len);
}

// Where the value of `key` (quoted, e.g. "'descr'") starts in the dict.
std::size_t value_after(const std::string& path, const char* noun, const std::string& header,
                        const char* key) {
  const std::size_t k = header.find(key);
  if (k == std::string::npos) fail_npy(path, noun, std::string("header has no ") + key);
  std::size_t p = header.find(':', k);
  if (p == std::string::npos) fail_npy(path, noun, "bad header");
  ++p;
  while (p < header.size() && header[p] == ' ') ++p;
  return p;
}

void parse_dtype(const std::string& path, const char* noun, const std::string& header,
                 NpyHeader* h) {
  const std::size_t p = value_after(path, noun, header, "'descr'");
  if (p >= header.size() || (header[p] != '\'' && header[p] != '"')) {
    fail_npy(path, noun, "structured dtypes are not supported (use a bool or uint8 array)");
  }
  const std::size_t q = header.find(header[p], p + 1);
  if (q == std::string::npos) fail_npy(path, noun, "bad header");
  h->descr = header.substr(p + 1, q - p - 1);
  const std::string& descr = h->descr;
  if (descr.size() < 3) fail_npy(path, noun, "dtype '" + descr + "' is not supported");
  const char order = descr[0];
  const char kind = descr[1];
  unsigned long long item_size = 0;
  if (!parse_count(std::string_view(descr).substr(2), &item_size) ||
      std::strchr("<>|=", order) == nullptr ||
      !((kind == 'b' && item_size == 1) ||
        ((kind == 'u' || kind == 'i') &&
         (item_size == 1 || item_size == 2 || item_size == 4 || item_size == 8)) ||
        (kind == 'f' && (item_size == 4 || item_size == 8)))) {
    fail_npy(path, noun, "dtype '" + descr + "' is not supported (use bool, an integer or a float type)");
  }
  h->kind = kind;
  h->big = order == '>';
  h->item_size = static_cast<std::size_t>(item_size);
}

std::vector<unsigned long long> parse_shape(const std::string& path, const char* noun,
                                            const std::string& header) {
  const std::size_t p = value_after(path, noun, header, "'shape'");
  if (p >= header.size() || header[p] != '(') fail_npy(path, noun, "bad shape in the header");
  const std::size_t close = header.find(')', p);
  if (close == std::string::npos) fail_npy(path, noun, "bad shape in the header");
  std::vector<unsigned long long> shape;
  std::string_view s(header.data() + p + 1, close - p - 1);
  while (!s.empty()) {
    while (!s.empty() && (s.front() == ' ' || s.front() == ',')) s.remove_prefix(1);
    if (s.empty()) break;
    std::size_t e = 0;
    while (e < s.size() && s[e] != ',' && s[e] != ' ') ++e;
    unsigned long long v;
    std::string_view num = s.substr(0, e);
    if (!num.empty() && num.back() == 'L') num.remove_suffix(1);  // Python 2 longs
    if (!parse_count(num, &v)) fail_npy(path, noun, "bad shape in the header");
    shape.push_back(v);
    s.remove_prefix(e);
  }
  return shape;
}

}  // namespace

NpyHeader read_npy_header(const std::string& path, const std::string& d, const char* noun) {
  NpyHeader h;
  const std::string header = header_dict(path, d, noun, &h.data_start);
  parse_dtype(path, noun, header, &h);
  const std::size_t p = value_after(path, noun, header, "'fortran_order'");
  if (header.compare(p, 4, "True") == 0) {
    h.fortran = true;
  } else if (header.compare(p, 5, "False") == 0) {
    h.fortran = false;
  } else {
    fail_npy(path, noun, "bad fortran_order in the header");
  }
  h.shape = parse_shape(path, noun, header);
  return h;
}

// The shape as Python prints it: "(3, 4, 5)", "(7,)".
std::string npy_shape_text(const std::vector<unsigned long long>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    text += (i ? ", " : "") + std::to_string(shape[i]);
  }
  text += shape.size() == 1 ? ",)" : ")";
  return text;
}


void check_npy_data_size(const std::string& path, const std::string& d, const NpyHeader& h,
                         unsigned long long count) {
  const unsigned long long need = count * h.item_size;
  const std::size_t have = d.size() - h.data_start;
  if (have < need) {
    fail(quoted(path) + " is truncated: shape " + npy_shape_text(h.shape) + " of " + h.descr +
         " needs " + std::to_string(need) + " data bytes, the file has " + std::to_string(have));
  }
  if (have > need) {
    fail(quoted(path) + " has " + std::to_string(have - need) +
         " bytes more than its header's shape and dtype need (not a valid .npy)");
  }
}

double npy_value(const NpyHeader& h, const unsigned char* e) {
  switch (h.kind) {
    case 'f':
      return h.item_size == 4 ? load<float>(e, h.big) : load<double>(e, h.big);
    case 'b':
      return e[0] != 0 ? 1 : 0;
    case 'u':
      switch (h.item_size) {
        case 1: return e[0];
        case 2: return load<std::uint16_t>(e, h.big);
        case 4: return load<std::uint32_t>(e, h.big);
        default: return static_cast<double>(load<std::uint64_t>(e, h.big));
      }
    default:
      switch (h.item_size) {
        case 1: return static_cast<std::int8_t>(e[0]);
        case 2: return load<std::int16_t>(e, h.big);
        case 4: return load<std::int32_t>(e, h.big);
        default: return static_cast<double>(load<std::int64_t>(e, h.big));
      }
  }
}

}  // namespace csgfit::io_detail
