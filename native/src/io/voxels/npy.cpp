// NumPy .npy voxel grids: a 3-D array, non-zero = solid.

#include <climits>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/npy_array.h"
#include "io/voxels/formats.h"

namespace csgfit::io_detail {

namespace {

// Checks the shape and the data size against the header; returns the number of voxels.
unsigned long long checked_voxel_count(const std::string& path, const std::string& d,
                                       const NpyHeader& h, const VoxelReadOptions& options) {
  const std::string shape = npy_shape_text(h.shape);
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
  check_npy_data_size(path, d, h, total);
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
  const NpyHeader h = read_npy_header(path, d, "voxel grid");
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
