// Internal to model/: word-level operations of the bit-packed grids.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace csgfit::bit_words {

inline std::size_t popcount(std::uint64_t w) {
  return static_cast<std::size_t>(__builtin_popcountll(w));
}

/// Sets bits [begin, end) of a row that starts at `row`.
inline void set_span(std::uint64_t* row, int begin, int end) {
  if (begin >= end) return;
  const int first = begin >> 6;
  const int last = (end - 1) >> 6;
  const std::uint64_t head = ~std::uint64_t{0} << (begin & 63);
  const int tail_bits = end & 63;
  const std::uint64_t tail =
      tail_bits ? (~std::uint64_t{0} >> (64 - tail_bits)) : ~std::uint64_t{0};
  if (first == last) {
    row[first] |= head & tail;
    return;
  }
  row[first] |= head;
  for (int i = first + 1; i < last; ++i) row[i] = ~std::uint64_t{0};
  row[last] |= tail;
}

/// Set bits of all words.
inline std::size_t count(const std::vector<std::uint64_t>& words) {
  std::size_t n = 0;
  for (std::uint64_t w : words) n += popcount(w);
  return n;
}

/// Clears the padding bits past `width` in the last word of every row (rows of
/// `words_per_row` words).
inline void mask_padding(std::vector<std::uint64_t>& words, int width, int words_per_row) {
  const int tail_bits = width & 63;
  if (tail_bits == 0 || words_per_row == 0) return;
  const std::uint64_t mask = ~std::uint64_t{0} >> (64 - tail_bits);
  for (std::size_t w = static_cast<std::size_t>(words_per_row) - 1; w < words.size();
       w += static_cast<std::size_t>(words_per_row))
    words[w] &= mask;
}

/// a[i] = op(a[i], b[i]) for every word (the grids' union, intersection and difference).
template <typename Op>
void combine(std::vector<std::uint64_t>& a, const std::vector<std::uint64_t>& b, Op op) {
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = op(a[i], b[i]);
}

inline std::uint64_t unite(std::uint64_t a, std::uint64_t b) { return a | b; }
inline std::uint64_t intersect(std::uint64_t a, std::uint64_t b) { return a & b; }
inline std::uint64_t subtract(std::uint64_t a, std::uint64_t b) { return a & ~b; }

}  // namespace csgfit::bit_words
