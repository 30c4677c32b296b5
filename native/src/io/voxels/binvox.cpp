// binvox: "#binvox 1", header lines up to "data", then (value, count) byte pairs.

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/sniff.h"
#include "io/text_tokens.h"
#include "io/voxels/formats.h"

namespace csgfit::io_detail {

namespace {

struct BinvoxHeader {
  unsigned long long dims[3] = {0, 0, 0};
  double translate[3] = {0, 0, 0};
  double scale = 1;
  std::size_t body = 0;  // where the run-length data starts
};

BinvoxHeader read_header(const std::string& path, const std::string& d) {
  if (!starts_with(d, "#binvox")) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a binvox voxel grid");
    fail(quoted(path) + " is not a binvox file (it does not start with '#binvox')");
  }
  // The run-length data follows the newline of the "data" line.
  const std::size_t data_kw = d.find("\ndata");
  if (data_kw == std::string::npos) {
    fail(quoted(path) + " is truncated (no 'data' line in the binvox header)");
  }
  BinvoxHeader h;
  h.body = data_kw + 5;
  while (h.body < d.size() && d[h.body] == '\r') ++h.body;
  if (h.body < d.size() && d[h.body] == '\n') ++h.body;
  Cursor c{d.data(), d.data() + data_kw};
  skip_line(c);
  bool have_dim = false;
  auto bad = [&](const std::string& what) {
    fail(quoted(path) + " line " + std::to_string(c.line) + ": bad binvox header (" + what + ")");
  };
  while (!c.at_end()) {
    std::string_view line = take_line(c);
    const std::string_view key = take_token(&line);
    if (key.empty()) continue;
    if (key == "dim") {
      for (auto& v : h.dims) {
        if (!parse_count(take_token(&line), &v) || v == 0) bad("dim needs 3 positive sizes");
      }
      have_dim = true;
    } else if (key == "translate") {
      for (double& v : h.translate) {
        if (!parse_double(take_token(&line), &v) || !std::isfinite(v)) {
          bad("translate needs 3 numbers");
        }
      }
    } else if (key == "scale") {
      if (!parse_double(take_token(&line), &h.scale) || !std::isfinite(h.scale) || h.scale <= 0) {
        bad("scale must be a positive number");
      }
    } else {
      bad("unknown keyword '" + std::string(key) + "'");
    }
  }
  if (!have_dim) fail(quoted(path) + ": bad binvox header (no dim line)");
  return h;
}

}  // namespace

VoxelGrid read_binvox(const std::string& path, const std::string& d,
                      const VoxelReadOptions& options) {
  const BinvoxHeader h = read_header(path, d);
  const unsigned long long* dims = h.dims;
  unsigned long long total = 1;
  for (unsigned long long s : h.dims) {
    if (s > static_cast<unsigned long long>(INT_MAX) / 2 || total > options.max_voxels / s) {
      fail(quoted(path) + " has " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
           " x " + std::to_string(dims[2]) + " voxels, over the limit of " +
           std::to_string(options.max_voxels));
    }
    total *= s;
  }
  // A (value, count) pair covers at most 255 voxels: data too short to fill the grid is
  // refused before the grid is allocated.
  const unsigned long long pairs = (d.size() - std::min(h.body, d.size())) / 2;
  if (pairs * 255 < total) {
    fail(quoted(path) + " is truncated: its run-length data covers at most " +
         std::to_string(pairs * 255) + " of " + std::to_string(total) + " voxels");
  }
  // binvox: "dim depth height width"; the x index is the most significant, then z, then y
  // (y runs fastest): index = (x * dz + z) * dy + y.
  const unsigned long long nx = dims[0], nz = dims[1], ny = dims[2];
  const double size = h.scale / static_cast<double>(std::max({nx, nz, ny}));
  VoxelGrid grid(static_cast<int>(nx), static_cast<int>(ny), static_cast<int>(nz), h.translate[0],
                 h.translate[1], h.translate[2], size);
  const unsigned char* u = bytes_of(d);
  std::size_t pos = std::min(h.body, d.size());
  unsigned long long n = 0;
  while (n < total) {
    if (pos + 2 > d.size()) {
      fail(quoted(path) + " is truncated: its run-length data covers " + std::to_string(n) +
           " of " + std::to_string(total) + " voxels");
    }
    const unsigned char value = u[pos];
    const unsigned long long run = u[pos + 1];
    pos += 2;
    if (run > total - n) {
      fail(quoted(path) + ": bad binvox data (a run goes past the " + std::to_string(total) +
           " voxels of the grid)");
    }
    if (value != 0) {
      for (unsigned long long m = n; m < n + run; ++m) {
        grid.set(static_cast<int>(m / (ny * nz)), static_cast<int>(m % ny),
                 static_cast<int>((m / ny) % nz));
      }
    }
    n += run;
  }
  return grid;
}

}  // namespace csgfit::io_detail
