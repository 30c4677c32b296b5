#include "csgfit/model/bitmap.h"

#include <algorithm>
#include <stdexcept>

namespace csgfit {

namespace {
inline std::size_t popcount(std::uint64_t w) { return static_cast<std::size_t>(__builtin_popcountll(w)); }
}  // namespace

Bitmap::Bitmap(int width, int height) : width_(width), height_(height) {
  if (width < 0 || height < 0) throw std::invalid_argument("bitmap size must not be negative");
  words_per_row_ = (width + 63) / 64;
  bits_.assign(static_cast<std::size_t>(words_per_row_) * static_cast<std::size_t>(height), 0);
}

void Bitmap::set_span(int row, int col_begin, int col_end) {
  if (col_begin >= col_end) return;
  std::uint64_t* w = row_words(row);
  const int first = col_begin >> 6;
  const int last = (col_end - 1) >> 6;
  const std::uint64_t head = ~std::uint64_t{0} << (col_begin & 63);
  const int tail_bits = col_end & 63;
  const std::uint64_t tail = tail_bits ? (~std::uint64_t{0} >> (64 - tail_bits)) : ~std::uint64_t{0};
  if (first == last) {
    w[first] |= head & tail;
    return;
  }
  w[first] |= head;
  for (int i = first + 1; i < last; ++i) w[i] = ~std::uint64_t{0};
  w[last] |= tail;
}

void Bitmap::clear() { std::fill(bits_.begin(), bits_.end(), 0); }

void Bitmap::fill() {
  std::fill(bits_.begin(), bits_.end(), ~std::uint64_t{0});
  mask_padding();
}

void Bitmap::mask_padding() {
  const int tail_bits = width_ & 63;
  if (tail_bits == 0 || words_per_row_ == 0) return;
  const std::uint64_t mask = ~std::uint64_t{0} >> (64 - tail_bits);
  for (int r = 0; r < height_; ++r) row_words(r)[words_per_row_ - 1] &= mask;
}

std::size_t Bitmap::count() const {
  std::size_t n = 0;
  for (std::uint64_t w : bits_) n += popcount(w);
  return n;
}

Bitmap& Bitmap::operator|=(const Bitmap& o) {
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] |= o.bits_[i];
  return *this;
}

Bitmap& Bitmap::operator&=(const Bitmap& o) {
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] &= o.bits_[i];
  return *this;
}

Bitmap& Bitmap::subtract(const Bitmap& o) {
  for (std::size_t i = 0; i < bits_.size(); ++i) bits_[i] &= ~o.bits_[i];
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

std::size_t count_and_not(const Bitmap& a, const Bitmap& b) {
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] & ~pb[i]);
  return n;
}

std::size_t count_and(const Bitmap& a, const Bitmap& b) {
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] & pb[i]);
  return n;
}

std::size_t count_xor(const Bitmap& a, const Bitmap& b) {
  std::size_t n = 0;
  const std::uint64_t* pa = a.data();
  const std::uint64_t* pb = b.data();
  for (std::size_t i = 0; i < a.word_count(); ++i) n += popcount(pa[i] ^ pb[i]);
  return n;
}

double iou(const Bitmap& a, const Bitmap& b) {
  const std::size_t inter = count_and(a, b);
  const std::size_t uni = a.count() + b.count() - inter;
  return uni == 0 ? 1.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

}  // namespace csgfit
