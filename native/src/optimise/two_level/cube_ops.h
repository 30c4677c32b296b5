// Bit-row helpers shared by the two-level minimisers (internal).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/optimise/two_level.h"

namespace csgfit::two_level::detail {

inline std::size_t words_for(std::size_t variables) { return (variables + 63) / 64; }
inline bool test_bit(const BitRow& row, std::size_t i) { return (row[i / 64] >> (i % 64)) & 1U; }
inline void clear_bit(BitRow& row, std::size_t i) { row[i / 64] &= ~(std::uint64_t{1} << (i % 64)); }
std::size_t popcount(const BitRow& row);

/// The cube of one minterm: every variable a literal.
Cube minterm_cube(const BitRow& minterm, std::size_t variables);
/// The smallest cube holding all `minterms` (non-empty, all of one width).
Cube supercube(const std::vector<BitRow>& minterms, std::size_t variables);
/// Whether `outer` holds every minterm of `inner`.
bool cube_contains(const Cube& outer, const Cube& inner);
/// Whether any of `minterms` is in `cube`.
bool meets_any(const Cube& cube, const std::vector<BitRow>& minterms);

/// Drops the cube's literals in `order` (variable indices) one at a time while the cube stays
/// clear of `off` (which it must be on entry); every literal left is needed, so the result is a
/// prime implicant of on + don't-cares.
Cube expand(const Cube& cube, const std::vector<BitRow>& off, const std::vector<std::size_t>& order);

/// A cover's size as the seed counts it: cubes first, then literals.
struct Cost {
  std::size_t cubes = 0, literals = 0;
  bool operator<(const Cost& o) const {
    return cubes != o.cubes ? cubes < o.cubes : literals < o.literals;
  }
};
Cost cost_of(const Cover& cover);

/// Greedy set cover completing `chosen`: the subset covering most uncovered elements first
/// (ties: lowest index).
std::vector<std::size_t> greedy_cover(const SetCoverInstance& instance,
                                      std::vector<std::size_t> chosen = {});
/// Drops chosen subsets whose elements are all covered twice, smallest subsets first.
void drop_redundant(const SetCoverInstance& instance, std::vector<std::size_t>& chosen);

}  // namespace csgfit::two_level::detail
