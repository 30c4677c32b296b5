#include "csgfit/model/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace csgfit {

namespace {
inline std::size_t popcount(std::uint64_t w) {
  return static_cast<std::size_t>(__builtin_popcountll(w));
}

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
  bits_.assign(static_cast<std::size_t>(words_per_row_) * rows, 0);
}

void VoxelGrid::set_span(int j, int k, int i_begin, int i_end) {
  if (i_begin >= i_end) return;
  std::uint64_t* w = row_words(j, k);
  const int first = i_begin >> 6;
  const int last = (i_end - 1) >> 6;
  const std::uint64_t head = ~std::uint64_t{0} << (i_begin & 63);
  const int tail_bits = i_end & 63;
  const std::uint64_t tail =
      tail_bits ? (~std::uint64_t{0} >> (64 - tail_bits)) : ~std::uint64_t{0};
  if (first == last) {
    w[first] |= head & tail;
    return;
  }
  w[first] |= head;
  for (int i = first + 1; i < last; ++i) w[i] = ~std::uint64_t{0};
  w[last] |= tail;
}

void VoxelGrid::clear() { std::fill(bits_.begin(), bits_.end(), 0); }

void VoxelGrid::fill() {
  std::fill(bits_.begin(), bits_.end(), ~std::uint64_t{0});
  const int tail_bits = nx_ & 63;
  if (tail_bits == 0 || words_per_row_ == 0) return;
  // Padding bits stay zero so whole-word counts need no masking.
  const std::uint64_t mask = ~std::uint64_t{0} >> (64 - tail_bits);
  for (std::size_t w = static_cast<std::size_t>(words_per_row_) - 1; w < bits_.size();
       w += static_cast<std::size_t>(words_per_row_))
    bits_[w] &= mask;
}

std::size_t VoxelGrid::count() const {
  std::size_t n = 0;
  for (std::uint64_t w : bits_) n += popcount(w);
  return n;
}

VoxelGrid& VoxelGrid::operator|=(const VoxelGrid& o) {
  require_same_shape(*this, o);
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] |= o.bits_[i];
  return *this;
}

VoxelGrid& VoxelGrid::operator&=(const VoxelGrid& o) {
  require_same_shape(*this, o);
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] &= o.bits_[i];
  return *this;
}

VoxelGrid& VoxelGrid::subtract(const VoxelGrid& o) {
  require_same_shape(*this, o);
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] &= ~o.bits_[i];
  return *this;
}

bool VoxelGrid::operator==(const VoxelGrid& o) const {
  return nx_ == o.nx_ && ny_ == o.ny_ && nz_ == o.nz_ && ox_ == o.ox_ && oy_ == o.oy_ &&
         oz_ == o.oz_ && size_ == o.size_ && bits_ == o.bits_;
}

std::size_t count_and_not(const VoxelGrid& a, const VoxelGrid& b) {
  require_same_shape(a, b);
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] & ~pb[i]);
  return n;
}

std::size_t count_and(const VoxelGrid& a, const VoxelGrid& b) {
  require_same_shape(a, b);
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] & pb[i]);
  return n;
}

std::size_t count_xor(const VoxelGrid& a, const VoxelGrid& b) {
  require_same_shape(a, b);
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] ^ pb[i]);
  return n;
}

double iou(const VoxelGrid& a, const VoxelGrid& b) {
  const std::size_t inter = count_and(a, b);
  const std::size_t uni = a.count() + b.count() - inter;
  return uni == 0 ? 1.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

}  // namespace csgfit
