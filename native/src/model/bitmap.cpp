#include "csgfit/model/bitmap.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "csgfit/model/memory_budget.h"
#include "model/bit_words.h"

namespace csgfit {

Bitmap::Bitmap(int width, int height) : width_(width), height_(height) {
  if (width < 0 || height < 0) throw std::invalid_argument("bitmap size must not be negative");
  words_per_row_ = (width + 63) / 64;
  check_allocation(8.0 * words_per_row_ * height,
                   "a " + std::to_string(width) + " x " + std::to_string(height) + " raster");
  bits_.assign(static_cast<std::size_t>(words_per_row_) * static_cast<std::size_t>(height), 0);
}

void Bitmap::set_span(int row, int col_begin, int col_end) {
  bit_words::set_span(row_words(row), col_begin, col_end);
}

void Bitmap::clear() { std::fill(bits_.begin(), bits_.end(), 0); }

void Bitmap::fill() {
  std::fill(bits_.begin(), bits_.end(), ~std::uint64_t{0});
  mask_padding();
}

void Bitmap::mask_padding() { bit_words::mask_padding(bits_, width_, words_per_row_); }

std::size_t Bitmap::count() const { return bit_words::count(bits_); }

Bitmap& Bitmap::operator|=(const Bitmap& o) {
  bit_words::combine(bits_, o.bits_, bit_words::unite);
  return *this;
}

Bitmap& Bitmap::operator&=(const Bitmap& o) {
  bit_words::combine(bits_, o.bits_, bit_words::intersect);
  return *this;
}

Bitmap& Bitmap::subtract(const Bitmap& o) {
  bit_words::combine(bits_, o.bits_, bit_words::subtract);
  return *this;
}

void Bitmap::or_rows(const Bitmap& o, int row_begin, int row_end) {
  const std::size_t end = static_cast<std::size_t>(row_end) * words_per_row_;
  for (std::size_t i = static_cast<std::size_t>(row_begin) * words_per_row_; i < end; ++i)
    bits_[i] |= o.bits_[i];
}

void Bitmap::subtract_rows(const Bitmap& o, int row_begin, int row_end) {
  const std::size_t end = static_cast<std::size_t>(row_end) * words_per_row_;
  for (std::size_t i = static_cast<std::size_t>(row_begin) * words_per_row_; i < end; ++i)
    bits_[i] &= ~o.bits_[i];
}

Bitmap Bitmap::inverted() const {
  Bitmap out = *this;
  for (std::uint64_t& w : out.bits_) w = ~w;
  out.mask_padding();
  return out;
}

}  // namespace csgfit
