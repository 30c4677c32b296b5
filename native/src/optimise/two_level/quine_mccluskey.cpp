// Quine-McCluskey: every prime implicant of on + don't-cares by merging, then an exact cover.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace {

constexpr std::size_t kHardLimit = 30;  // 2^n minterms are enumerated, as 32-bit masks

// A cube of at most 32 variables as one key: care mask high, value low.
using Key = std::uint64_t;
Key key_of(std::uint64_t care, std::uint64_t value) { return care << 32 | value; }

// One merge round: two implicants with one care, differing in one variable only, make an
// implicant without it; those merged into nothing are prime.
std::vector<Key> merge_round(const std::vector<Key>& level, std::size_t variables,
                             std::vector<Key>& primes) {
  const std::unordered_set<Key> present(level.begin(), level.end());
  std::unordered_set<Key> merged, next;
  for (Key k : level) {
    const std::uint64_t care = k >> 32, value = k & 0xffffffffU;
    for (std::size_t i = 0; i < variables; ++i) {
      const std::uint64_t bit = std::uint64_t{1} << i;
      if (!(care & bit) || (value & bit) || !present.count(key_of(care, value | bit))) continue;
      merged.insert(k);
      merged.insert(key_of(care, value | bit));
      next.insert(key_of(care & ~bit, value));
    }
  }
  for (Key k : level)
    if (!merged.count(k)) primes.push_back(k);
  std::vector<Key> out(next.begin(), next.end());
  std::sort(out.begin(), out.end());
  return out;
}

Cube cube_of(Key k) { return Cube{BitRow{k >> 32}, BitRow{k & 0xffffffffU}}; }

}  // namespace

Cover quine_mccluskey(const TruthTable& table, std::size_t max_variables) {
  const TruthTable t = deduplicated(table);
  const std::size_t limit = std::min(max_variables, kHardLimit);
  if (t.variables > limit)
    throw std::length_error("quine_mccluskey: " + std::to_string(t.variables) +
                            " variables exceed the limit of " + std::to_string(limit) +
                            " (don't-cares are enumerated)");
  if (t.on.empty()) return {};
  if (t.variables == 0) return {Cube{}};
  const std::uint64_t all = (std::uint64_t{1} << t.variables) - 1;
  std::vector<bool> off(all + 1, false);
  for (const BitRow& m : t.off) off[m[0]] = true;
  std::vector<Key> level, primes;
  for (std::uint64_t m = 0; m <= all; ++m)
    if (!off[m]) level.push_back(key_of(all, m));
  while (!level.empty()) level = merge_round(level, t.variables, primes);
  std::vector<Cube> cubes;
  for (Key k : primes) {
    Cube cube = cube_of(k);
    if (detail::meets_any(cube, t.on)) cubes.push_back(std::move(cube));
  }
  Cover cover;
  for (std::size_t i : set_cover_exact(cover_instance(t.on, cubes)).chosen) cover.push_back(cubes[i]);
  return cover;
}

}  // namespace csgfit::two_level
