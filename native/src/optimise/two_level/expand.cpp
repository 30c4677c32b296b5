// EXPAND against an explicit off-set: the step shared by the seed's prime implicants and
// espresso.
#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level::detail {
namespace {

std::size_t lowest_bit(const BitRow& row) {
  for (std::size_t w = 0; w < row.size(); ++w)
    if (row[w] != 0) return w * 64 + static_cast<std::size_t>(__builtin_ctzll(row[w]));
  return row.size() * 64;
}

// Each off-minterm's conflict: the cube's literals it violates. A literal may be dropped iff
// no off-minterm violates that literal alone, so only the single-conflict rows need watching.
struct Conflicts {
  std::vector<BitRow> rows;
  std::vector<std::size_t> counts;
  BitRow blocked;

  void block_if_single(std::size_t k) {
    if (counts[k] == 1) {
      const std::size_t i = lowest_bit(rows[k]);
      blocked[i / 64] |= std::uint64_t{1} << (i % 64);
    }
  }
};

Conflicts conflicts_of(const Cube& cube, const std::vector<BitRow>& off) {
  Conflicts c{{}, {}, BitRow(cube.care.size(), 0)};
  c.rows.reserve(off.size());
  for (const BitRow& m : off) {
    BitRow row(m.size());
    for (std::size_t w = 0; w < m.size(); ++w) row[w] = (m[w] ^ cube.value[w]) & cube.care[w];
    c.rows.push_back(std::move(row));
    c.counts.push_back(popcount(c.rows.back()));
    c.block_if_single(c.rows.size() - 1);
  }
  return c;
}

}  // namespace

Cube expand(const Cube& cube, const std::vector<BitRow>& off, const std::vector<std::size_t>& order) {
  Conflicts c = conflicts_of(cube, off);
  Cube out = cube;
  for (std::size_t i : order) {
    if (!test_bit(out.care, i) || test_bit(c.blocked, i)) continue;
    clear_bit(out.care, i);
    clear_bit(out.value, i);
    for (std::size_t k = 0; k < c.rows.size(); ++k) {
      if (!test_bit(c.rows[k], i)) continue;
      clear_bit(c.rows[k], i);
      --c.counts[k];
      c.block_if_single(k);
    }
  }
  return out;
}

}  // namespace csgfit::two_level::detail
