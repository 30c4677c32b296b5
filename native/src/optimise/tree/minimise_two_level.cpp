#include <set>

#include "csgfit/optimise/redundancy.h"
#include "csgfit/optimise/structural_rules.h"
#include "csgfit/optimise/two_level.h"
#include "stages.h"

namespace csgfit::opt {
namespace {

// Beyond this many halfspaces a remaining solid is kept as it is: its truth table would be
// as large as the samples and its cover no smaller than the tree.
constexpr std::size_t kMaxTwoLevelVariables = 128;

template <std::size_t D>
two_level::TruthTable sampled_truth_table(const Expr& solid, const std::vector<int>& vars,
                                          const SampleSet<D>& s) {
  const Column inside = s.evaluate(solid);
  const std::size_t words = (vars.size() + 63) / 64;
  std::set<two_level::BitRow> on, off;
  for (std::size_t i = 0; i < s.point_count(); ++i) {
    two_level::BitRow row(words, 0);
    bool in_some = false;
    for (std::size_t v = 0; v < vars.size(); ++v) {
      if ((s.column(vars[v])[i / 64] >> (i % 64)) & 1) {
        row[v / 64] |= 1ULL << (v % 64);
        in_some = true;
      }
    }
    const bool in_solid = (inside[i / 64] >> (i % 64)) & 1;
    if (in_solid) on.insert(row);
    else if (in_some) off.insert(row);
  }
  off.insert(two_level::BitRow(words, 0));  // outside every halfspace is outside the solid
  two_level::TruthTable table;
  table.variables = vars.size();
  table.on.assign(on.begin(), on.end());
  table.off.assign(off.begin(), off.end());
  return table;
}

// A product of literals as an expression: (h1 & h2) - h3 - h4.
Expr product(const two_level::Cube& cube, const std::vector<int>& vars) {
  std::vector<Expr> pos, neg;
  for (std::size_t v = 0; v < vars.size(); ++v) {
    if (!((cube.care[v / 64] >> (v % 64)) & 1)) continue;
    const bool positive = (cube.value[v / 64] >> (v % 64)) & 1;
    (positive ? pos : neg).push_back(Expr::halfspace(vars[v]));
  }
  Expr base = pos.size() == 1 ? std::move(pos[0]) : Expr::make(ExprOp::Intersection, std::move(pos));
  if (neg.empty()) return base;
  neg.insert(neg.begin(), std::move(base));
  return Expr::make(ExprOp::Difference, std::move(neg));
}

two_level::Cover minimise(const two_level::TruthTable& table, RemainingMethod method, std::uint64_t seed) {
  switch (method) {
    case RemainingMethod::QuineMcCluskey:
      // It lists every implicant of the don't-cares (up to 3^n): past 12 halfspaces the
      // heuristic takes over.
      if (table.variables <= 12) return two_level::quine_mccluskey(table, 12);
      return two_level::espresso(table);
    case RemainingMethod::SetCover: return two_level::set_cover_minimise(table, table.on.size() <= 64, seed);
    default: return two_level::espresso(table);
  }
}

}  // namespace

template <std::size_t D>
Expr minimise_two_level(const Expr& solid, const SampleSet<D>& s, RemainingMethod method, std::uint64_t seed) {
  const std::vector<int> vars = halfspaces_used(solid);
  if (vars.size() < 2 || vars.size() > kMaxTwoLevelVariables) return solid;
  const two_level::TruthTable table = sampled_truth_table(solid, vars, s);
  if (table.on.empty()) return Expr::empty();
  const two_level::Cover cover = minimise(table, method, seed);
  std::vector<Expr> products;
  for (const auto& cube : cover) products.push_back(product(cube, vars));
  Expr candidate = products.size() == 1 ? std::move(products[0]) : Expr::make(ExprOp::Union, std::move(products));
  remove_redundancy(candidate, s);
  // The cover is free on the minterms no sample saw; it stands only where the dense check
  // finds it the same solid.
  if (expression_size(candidate) >= expression_size(solid) || !same_solid(candidate, solid, s)) return solid;
  return candidate;
}

template Expr minimise_two_level<2>(const Expr&, const SampleSet<2>&, RemainingMethod, std::uint64_t);
template Expr minimise_two_level<3>(const Expr&, const SampleSet<3>&, RemainingMethod, std::uint64_t);

}  // namespace csgfit::opt
