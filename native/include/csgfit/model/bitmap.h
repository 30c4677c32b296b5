// Bit-packed binary image: the grid every 2D stage works on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/model/bit_grid.h"

namespace csgfit {

/// A W x H binary image stored row by row, 64 pixels per word. Row 0 is the top row of the
/// image (as in the file); the solver's y axis points up, so pixel (col, row) has its centre at
/// (col + 0.5, H - row - 0.5) in pixel units. Bits past the width of a row are always zero, so
/// whole-word operations and popcounts need no masking.
class Bitmap {
 public:
  Bitmap() = default;
  /// An all-background bitmap. Throws std::invalid_argument on negative sizes.
  Bitmap(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  int words_per_row() const { return words_per_row_; }
  std::size_t word_count() const { return bits_.size(); }
  bool empty() const { return width_ == 0 || height_ == 0; }

  bool get(int col, int row) const {
    return (bits_[static_cast<std::size_t>(row) * words_per_row_ + (col >> 6)] >> (col & 63)) & 1u;
  }
  void set(int col, int row, bool value = true) {
    std::uint64_t& w = bits_[static_cast<std::size_t>(row) * words_per_row_ + (col >> 6)];
    const std::uint64_t bit = std::uint64_t{1} << (col & 63);
    w = value ? (w | bit) : (w & ~bit);
  }
  /// Sets pixels [col_begin, col_end) of one row; the range must lie inside the row.
  void set_span(int row, int col_begin, int col_end);
  void clear();
  void fill();

  /// Number of foreground pixels.
  std::size_t count() const;

  std::uint64_t* row_words(int row) { return bits_.data() + static_cast<std::size_t>(row) * words_per_row_; }
  const std::uint64_t* row_words(int row) const {
    return bits_.data() + static_cast<std::size_t>(row) * words_per_row_;
  }
  std::uint64_t* data() { return bits_.data(); }
  const std::uint64_t* data() const { return bits_.data(); }

  Bitmap& operator|=(const Bitmap& o);
  Bitmap& operator&=(const Bitmap& o);
  /// this = this AND NOT o.
  Bitmap& subtract(const Bitmap& o);
  /// The same operations restricted to rows [row_begin, row_end): the evaluator knows which
  /// rows a primitive can touch and skips the rest.
  void or_rows(const Bitmap& o, int row_begin, int row_end);
  void subtract_rows(const Bitmap& o, int row_begin, int row_end);
  /// Complement within the canvas (padding bits stay zero).
  Bitmap inverted() const;

  bool operator==(const Bitmap& o) const {
    return width_ == o.width_ && height_ == o.height_ && bits_ == o.bits_;
  }
  bool operator!=(const Bitmap& o) const { return !(*this == o); }

 private:
  void mask_padding();

  int width_ = 0;
  int height_ = 0;
  int words_per_row_ = 0;
  std::vector<std::uint64_t> bits_;
};

}  // namespace csgfit
