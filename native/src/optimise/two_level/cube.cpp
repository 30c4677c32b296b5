// Cubes over packed bit rows, and the contract all minimisers meet.
#include <algorithm>
#include <bitset>
#include <stdexcept>
#include <string>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace detail {

std::size_t popcount(const BitRow& row) {
  std::size_t count = 0;
  for (std::uint64_t word : row) count += std::bitset<64>(word).count();
  return count;
}

Cube minterm_cube(const BitRow& minterm, std::size_t variables) {
  Cube cube{BitRow(words_for(variables), ~std::uint64_t{0}), minterm};
  if (variables % 64 != 0) cube.care.back() = (std::uint64_t{1} << (variables % 64)) - 1;
  return cube;
}

Cube supercube(const std::vector<BitRow>& minterms, std::size_t variables) {
  Cube cube = minterm_cube(minterms.front(), variables);
  for (const BitRow& m : minterms)
    for (std::size_t w = 0; w < cube.care.size(); ++w) {
      cube.care[w] &= ~(m[w] ^ cube.value[w]);
      cube.value[w] &= cube.care[w];
    }
  return cube;
}

bool cube_contains(const Cube& outer, const Cube& inner) {
  for (std::size_t w = 0; w < outer.care.size(); ++w) {
    if (outer.care[w] & ~inner.care[w]) return false;
    if ((outer.value[w] ^ inner.value[w]) & outer.care[w]) return false;
  }
  return true;
}

bool meets_any(const Cube& cube, const std::vector<BitRow>& minterms) {
  return std::any_of(minterms.begin(), minterms.end(),
                     [&](const BitRow& m) { return cube.contains(m); });
}

Cost cost_of(const Cover& cover) {
  Cost cost{cover.size(), 0};
  for (const Cube& cube : cover) cost.literals += cube.literal_count();
  return cost;
}

}  // namespace detail

std::size_t Cube::literal_count() const { return detail::popcount(care); }

bool Cube::contains(const BitRow& minterm) const {
  for (std::size_t w = 0; w < care.size(); ++w)
    if ((minterm[w] ^ value[w]) & care[w]) return false;
  return true;
}

bool Cube::operator==(const Cube& o) const { return care == o.care && value == o.value; }

namespace {

void check_rows(const std::vector<BitRow>& rows, std::size_t variables, const char* which) {
  const std::size_t words = detail::words_for(variables);
  const std::uint64_t spare = variables % 64 == 0 ? 0 : ~((std::uint64_t{1} << (variables % 64)) - 1);
  for (const BitRow& row : rows)
    if (row.size() != words || (words > 0 && (row.back() & spare)))
      throw std::invalid_argument(std::string("truth table: an ") + which + "-minterm is not " +
                                  std::to_string(variables) + " bits wide");
}

void sort_unique(std::vector<BitRow>& rows) {
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
}

}  // namespace

TruthTable deduplicated(const TruthTable& table) {
  check_rows(table.on, table.variables, "on");
  check_rows(table.off, table.variables, "off");
  TruthTable out = table;
  sort_unique(out.on);
  sort_unique(out.off);
  std::vector<BitRow> both;
  std::set_intersection(out.on.begin(), out.on.end(), out.off.begin(), out.off.end(),
                        std::back_inserter(both));
  if (!both.empty())
    throw std::invalid_argument("truth table: " + std::to_string(both.size()) +
                                " minterm(s) are both on and off");
  return out;
}

bool covers_exactly(const TruthTable& table, const Cover& cover) {
  for (const Cube& cube : cover)
    if (detail::meets_any(cube, table.off)) return false;
  return std::all_of(table.on.begin(), table.on.end(), [&](const BitRow& m) {
    return std::any_of(cover.begin(), cover.end(), [&](const Cube& c) { return c.contains(m); });
  });
}

SetCoverInstance cover_instance(const std::vector<BitRow>& on, const std::vector<Cube>& cubes) {
  SetCoverInstance instance{on.size(), {}};
  for (const Cube& cube : cubes) {
    std::vector<std::size_t> covered;
    for (std::size_t i = 0; i < on.size(); ++i)
      if (cube.contains(on[i])) covered.push_back(i);
    instance.subsets.push_back(std::move(covered));
  }
  return instance;
}

}  // namespace csgfit::two_level
