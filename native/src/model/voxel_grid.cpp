#include "csgfit/model/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "csgfit/model/memory_budget.h"
#include "model/bit_words.h"

namespace csgfit {

namespace {
void require_same_shape(const VoxelGrid& a, const VoxelGrid& b) {
  if (a.nx() != b.nx() || a.ny() != b.ny() || a.nz() != b.nz())
    throw std::invalid_argument("voxel grids of different dimensions");
}
}  // namespace

VoxelGrid::VoxelGrid(int nx, int ny, int nz, double origin_x, double origin_y, double origin_z,
                     double voxel_size)
    : nx_(nx), ny_(ny), nz_(nz), ox_(origin_x), oy_(origin_y), oz_(origin_z), size_(voxel_size) {
  if (nx < 0 || ny < 0 || nz < 0) throw std::invalid_argument("voxel grid size must not be negative");
  if (!(voxel_size > 0) || !std::isfinite(voxel_size))
    throw std::invalid_argument("voxel size must be a positive finite number");
  if (!std::isfinite(origin_x) || !std::isfinite(origin_y) || !std::isfinite(origin_z))
    throw std::invalid_argument("voxel grid origin must be finite");
  words_per_row_ = (nx + 63) / 64;
  const std::size_t rows = static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz);
  // Guard the multiplication itself: a corrupt header must not wrap around to a small size.
  if (rows != 0 && static_cast<std::size_t>(words_per_row_) >
                       std::numeric_limits<std::size_t>::max() / sizeof(std::uint64_t) / rows)
    throw std::invalid_argument("voxel grid too large");
  check_allocation(8.0 * words_per_row_ * static_cast<double>(rows),
                   "a " + std::to_string(nx) + " x " + std::to_string(ny) + " x " +
                       std::to_string(nz) + " voxel grid");
  bits_.assign(static_cast<std::size_t>(words_per_row_) * rows, 0);
}

void VoxelGrid::set_span(int j, int k, int i_begin, int i_end) {
  bit_words::set_span(row_words(j, k), i_begin, i_end);
}

void VoxelGrid::clear() { std::fill(bits_.begin(), bits_.end(), 0); }

void VoxelGrid::fill() {
  std::fill(bits_.begin(), bits_.end(), ~std::uint64_t{0});
  // Padding bits stay zero so whole-word counts need no masking.
  bit_words::mask_padding(bits_, nx_, words_per_row_);
}

std::size_t VoxelGrid::count() const { return bit_words::count(bits_); }

VoxelGrid& VoxelGrid::operator|=(const VoxelGrid& o) {
  require_same_shape(*this, o);
  bit_words::combine(bits_, o.bits_, bit_words::unite);
  return *this;
}

VoxelGrid& VoxelGrid::operator&=(const VoxelGrid& o) {
  require_same_shape(*this, o);
  bit_words::combine(bits_, o.bits_, bit_words::intersect);
  return *this;
}

VoxelGrid& VoxelGrid::subtract(const VoxelGrid& o) {
  require_same_shape(*this, o);
  bit_words::combine(bits_, o.bits_, bit_words::subtract);
  return *this;
}

bool VoxelGrid::operator==(const VoxelGrid& o) const {
  return nx_ == o.nx_ && ny_ == o.ny_ && nz_ == o.nz_ && ox_ == o.ox_ && oy_ == o.oy_ &&
         oz_ == o.oz_ && size_ == o.size_ && bits_ == o.bits_;
}

}  // namespace csgfit
