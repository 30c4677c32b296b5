// count_and_not, count_and, count_xor and iou, once for Bitmap and VoxelGrid.
#include "csgfit/model/bit_grid.h"

#include <stdexcept>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/voxel_grid.h"
#include "model/bit_words.h"

namespace csgfit {

namespace {

// A bitmap's callers always compare canvases of one fit; voxel grids come from more places.
void require_same_shape(const Bitmap&, const Bitmap&) {}
void require_same_shape(const VoxelGrid& a, const VoxelGrid& b) {
  if (a.nx() != b.nx() || a.ny() != b.ny() || a.nz() != b.nz())
    throw std::invalid_argument("voxel grids of different dimensions");
}

template <typename Grid, typename Op>
std::size_t count_words(const Grid& a, const Grid& b, Op op) {
  require_same_shape(a, b);
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += bit_words::popcount(op(pa[i], pb[i]));
  return n;
}

}  // namespace

template <typename Grid>
std::size_t count_and_not(const Grid& a, const Grid& b) {
  return count_words(a, b, [](std::uint64_t x, std::uint64_t y) { return x & ~y; });
}

template <typename Grid>
std::size_t count_and(const Grid& a, const Grid& b) {
  return count_words(a, b, [](std::uint64_t x, std::uint64_t y) { return x & y; });
}

template <typename Grid>
std::size_t count_xor(const Grid& a, const Grid& b) {
  return count_words(a, b, [](std::uint64_t x, std::uint64_t y) { return x ^ y; });
}

template <typename Grid>
double iou(const Grid& a, const Grid& b) {
  const std::size_t inter = count_and(a, b);
  const std::size_t uni = a.count() + b.count() - inter;
  return uni == 0 ? 1.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

#define INSTANTIATE_BIT_GRID(Grid)                                   \
  template std::size_t count_and_not<Grid>(const Grid&, const Grid&); \
  template std::size_t count_and<Grid>(const Grid&, const Grid&);     \
  template std::size_t count_xor<Grid>(const Grid&, const Grid&);     \
  template double iou<Grid>(const Grid&, const Grid&)

INSTANTIATE_BIT_GRID(Bitmap);
INSTANTIATE_BIT_GRID(VoxelGrid);

}  // namespace csgfit
