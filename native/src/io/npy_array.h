// NumPy .npy arrays: the header (a magic string, a version, and a Python dict literal giving
// the dtype, the order and the shape) and the raw data after it, for every reader of arrays
// (voxel grids, depth images, organised point clouds).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace csgfit::io_detail {

/// What the header dict says.
struct NpyHeader {
  std::string descr;  // e.g. "<f4"
  char kind = 0;      // 'b', 'u', 'i' or 'f'
  bool big = false;
  std::size_t item_size = 0;
  bool fortran = false;
  std::vector<unsigned long long> shape;
  std::size_t data_start = 0;
};

/// The header of the .npy file `d`, refused with one line ("... is not a usable NumPy <noun>:
/// ...") for a bad signature, version, dtype, order or shape. Numeric dtypes only: bool,
/// integers of 1 to 8 bytes, float32 and float64.
NpyHeader read_npy_header(const std::string& path, const std::string& d, const char* noun);

/// The shape as Python prints it: "(3, 4, 5)", "(7,)".
std::string npy_shape_text(const std::vector<unsigned long long>& shape);

/// Refuses a file whose data is not exactly `count` items of the header's dtype (truncated, or
/// with trailing bytes).
void check_npy_data_size(const std::string& path, const std::string& d, const NpyHeader& h,
                         unsigned long long count);

/// The array element at `e` as a double (bool and integers exactly, floats as stored).
double npy_value(const NpyHeader& h, const unsigned char* e);

}  // namespace csgfit::io_detail
