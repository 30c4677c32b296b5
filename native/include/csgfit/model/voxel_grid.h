// Bit-packed voxel grid: the 3D counterpart of Bitmap.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/model/bit_grid.h"

namespace csgfit {

/// A regular grid of nx x ny x nz voxels placed in model space: voxel (i, j, k) is the box
/// [origin + (i, j, k) * voxel_size, origin + (i+1, j+1, k+1) * voxel_size], its centre at
/// origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size (a mesh keeps its own coordinates, z up).
/// Storage: x fastest, 64 voxels per word, each x-row padded to whole words (padding bits are
/// always zero), rows ordered by j then k.
class VoxelGrid {
 public:
  VoxelGrid() = default;
  /// An empty grid. Throws std::invalid_argument on negative sizes or a non-positive voxel size.
  VoxelGrid(int nx, int ny, int nz, double origin_x = 0, double origin_y = 0, double origin_z = 0,
            double voxel_size = 1);

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }
  double origin_x() const { return ox_; }
  double origin_y() const { return oy_; }
  double origin_z() const { return oz_; }
  double voxel_size() const { return size_; }
  int words_per_row() const { return words_per_row_; }
  std::size_t word_count() const { return bits_.size(); }
  bool empty() const { return nx_ == 0 || ny_ == 0 || nz_ == 0; }

  /// Centre of voxel (i, j, k) in model coordinates.
  double center_x(int i) const { return ox_ + (i + 0.5) * size_; }
  double center_y(int j) const { return oy_ + (j + 0.5) * size_; }
  double center_z(int k) const { return oz_ + (k + 0.5) * size_; }

  bool get(int i, int j, int k) const {
    return (row_words(j, k)[i >> 6] >> (i & 63)) & 1u;
  }
  void set(int i, int j, int k, bool value = true) {
    std::uint64_t& w = row_words(j, k)[i >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
    w = value ? (w | bit) : (w & ~bit);
  }
  /// Sets voxels [i_begin, i_end) of the x-row (j, k).
  void set_span(int j, int k, int i_begin, int i_end);
  void clear();
  void fill();
  /// Number of set voxels.
  std::size_t count() const;

  std::uint64_t* row_words(int j, int k) {
    return bits_.data() + (static_cast<std::size_t>(k) * ny_ + j) * words_per_row_;
  }
  const std::uint64_t* row_words(int j, int k) const {
    return bits_.data() + (static_cast<std::size_t>(k) * ny_ + j) * words_per_row_;
  }
  std::uint64_t* data() { return bits_.data(); }
  const std::uint64_t* data() const { return bits_.data(); }

  VoxelGrid& operator|=(const VoxelGrid& o);
  VoxelGrid& operator&=(const VoxelGrid& o);
  /// this = this AND NOT o.
  VoxelGrid& subtract(const VoxelGrid& o);

  /// Same dimensions, placement and bits.
  bool operator==(const VoxelGrid& o) const;
  bool operator!=(const VoxelGrid& o) const { return !(*this == o); }

 private:
  int nx_ = 0, ny_ = 0, nz_ = 0;
  double ox_ = 0, oy_ = 0, oz_ = 0, size_ = 1;
  int words_per_row_ = 0;
  std::vector<std::uint64_t> bits_;
};

}  // namespace csgfit
