// NumPy .npy: a magic string, a version, and a Python dict literal that gives the dtype, the
// order and the shape, then the raw array.

#include <climits>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/sniff.h"
#include "io/text_tokens.h"
#include "io/voxels/formats.h"

namespace csgfit::io_detail {

namespace {

[[noreturn]] void fail_npy(const std::string& path, const std::string& what) {
  fail(quoted(path) + " is not a usable NumPy voxel grid: " + what);
}

// What the header dict says.
struct NpyHeader {
  std::string descr;  // e.g. "<f4"
  char kind = 0;      // 'b', 'u', 'i' or 'f'
  bool big = false;
  std::size_t item_size = 0;
  bool fortran = false;
  std::vector<unsigned long long> shape;
  std::size_t data_start = 0;
};

// The header dict's text, after the signature and version; *data_start gets where the array
// begins.
std::string header_dict(const std::string& path, const std::string& d, std::size_t* data_start) {
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
    fail_npy(path, "unknown .npy version " + std::to_string(major));
  }
  if (header_len > d.size() - header_start) {
    fail(quoted(path) + " is truncated (NumPy header cut short)");
  }
  *data_start = header_start + header_len;
  return d.substr(header_start, header_len);
}

// Where the value of `key` (quoted, e.g. "'descr'") starts in the dict.
std::size_t value_after(const std::string& path, const std::string& header, const char* key) {
  const std::size_t k = header.find(key);
  if (k == std::string::npos) fail_npy(path, std::string("header has no ") + key);
  std::size_t p = header.find(':', k);
  if (p == std::string::npos) fail_npy(path, "bad header");
  ++p;
  while (p < header.size() && header[p] == ' ') ++p;
  return p;
}

void parse_dtype(const std::string& path, const std::string& header, NpyHeader* h) {
  const std::size_t p = value_after(path, header, "'descr'");
  if (p >= header.size() || (header[p] != '\'' && header[p] != '"')) {
    fail_npy(path, "structured dtypes are not supported (use a bool or uint8 array)");
  }
  const std::size_t q = header.find(header[p], p + 1);
  if (q == std::string::npos) fail_npy(path, "bad header");
  h->descr = header.substr(p + 1, q - p - 1);
  const std::string& descr = h->descr;
  if (descr.size() < 3) fail_npy(path, "dtype '" + descr + "' is not supported");
  const char order = descr[0];
  const char kind = descr[1];
  unsigned long long item_size = 0;
  if (!parse_count(std::string_view(descr).substr(2), &item_size) ||
      std::strchr("<>|=", order) == nullptr ||
      !((kind == 'b' && item_size == 1) ||
        ((kind == 'u' || kind == 'i') &&
         (item_size == 1 || item_size == 2 || item_size == 4 || item_size == 8)) ||
        (kind == 'f' && (item_size == 4 || item_size == 8)))) {
    fail_npy(path, "dtype '" + descr + "' is not supported (use bool, an integer or a float type)");
  }
  h->kind = kind;
  h->big = order == '>';
  h->item_size = static_cast<std::size_t>(item_size);
}

std::vector<unsigned long long> parse_shape(const std::string& path, const std::string& header) {
  const std::size_t p = value_after(path, header, "'shape'");
  if (p >= header.size() || header[p] != '(') fail_npy(path, "bad shape in the header");
  const std::size_t close = header.find(')', p);
  if (close == std::string::npos) fail_npy(path, "bad shape in the header");
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
    if (!parse_count(num, &v)) fail_npy(path, "bad shape in the header");
    shape.push_back(v);
    s.remove_prefix(e);
  }
  return shape;
}

NpyHeader read_header(const std::string& path, const std::string& d) {
  NpyHeader h;
  const std::string header = header_dict(path, d, &h.data_start);
  parse_dtype(path, header, &h);
  const std::size_t p = value_after(path, header, "'fortran_order'");
  if (header.compare(p, 4, "True") == 0) {
    h.fortran = true;
  } else if (header.compare(p, 5, "False") == 0) {
    h.fortran = false;
  } else {
    fail_npy(path, "bad fortran_order in the header");
  }
  h.shape = parse_shape(path, header);
  return h;
}

// The shape as Python prints it: "(3, 4, 5)", "(7,)".
std::string shape_text(const std::vector<unsigned long long>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    text += (i ? ", " : "") + std::to_string(shape[i]);
  }
  text += shape.size() == 1 ? ",)" : ")";
  return text;
}

// Checks the shape and the data size against the header; returns the number of voxels.
unsigned long long checked_voxel_count(const std::string& path, const std::string& d,
                                       const NpyHeader& h, const VoxelReadOptions& options) {
  const std::string shape = shape_text(h.shape);
  if (h.shape.size() != 3) {
    fail(quoted(path) + " has shape " + shape + ": a voxel grid must be a 3-D array");
  }
  unsigned long long total = 1;
  for (unsigned long long s : h.shape) {
    if (s == 0) fail(quoted(path) + " is an empty voxel grid (shape " + shape + ")");
    if (s > static_cast<unsigned long long>(INT_MAX) / 2 || total > options.max_voxels / s) {
      fail(quoted(path) + " has shape " + shape + ", over the limit of " +
           std::to_string(options.max_voxels) + " voxels");
    }
    total *= s;
  }
  const unsigned long long need = total * h.item_size;
  const std::size_t have = d.size() - h.data_start;
  if (have < need) {
    fail(quoted(path) + " is truncated: shape " + shape + " of " + h.descr + " needs " +
         std::to_string(need) + " data bytes, the file has " + std::to_string(have));
  }
  if (have > need) {
    fail(quoted(path) + " has " + std::to_string(have - need) +
         " bytes more than its header's shape and dtype need (not a valid .npy)");
  }
  return total;
}

// Whether the array element at e is non-zero; NaN is refused.
bool is_solid(const std::string& path, const NpyHeader& h, const unsigned char* e) {
  if (h.kind == 'f') {
    const double v = h.item_size == 4 ? load<float>(e, h.big) : load<double>(e, h.big);
    if (std::isnan(v)) fail(quoted(path) + " contains NaN values");
    return v != 0;
  }
  bool solid = false;
  for (std::size_t i = 0; i < h.item_size; ++i) solid = solid || e[i] != 0;
  return solid;
}

}  // namespace

VoxelGrid read_npy(const std::string& path, const std::string& d, const VoxelReadOptions& options) {
  const NpyHeader h = read_header(path, d);
  const unsigned long long total = checked_voxel_count(path, d, h, options);
  const std::size_t s0 = h.shape[0], s1 = h.shape[1], s2 = h.shape[2];
  VoxelGrid grid(static_cast<int>(s0), static_cast<int>(s1), static_cast<int>(s2));
  const unsigned char* data = bytes_of(d) + h.data_start;
  for (std::size_t n = 0; n < total; ++n) {
    if (!is_solid(path, h, data + n * h.item_size)) continue;
    std::size_t i, j, k;
    if (h.fortran) {  // first index fastest
      i = n % s0;
      j = (n / s0) % s1;
      k = n / (s0 * s1);
    } else {  // last index fastest
      k = n % s2;
      j = (n / s2) % s1;
      i = n / (s1 * s2);
    }
    grid.set(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
  }
  return grid;
}

}  // namespace csgfit::io_detail
