#include "csgfit/optimise/redundancy.h"

#include "csgfit/optimise/structural_rules.h"

namespace csgfit::opt {
namespace {

// The operands' columns (empty for opaque operands, which are then skipped).
template <std::size_t D>
std::vector<Column> operand_columns(const Expr& e, const SampleSet<D>& s, std::vector<bool>& known) {
  std::vector<Column> cols(e.kids.size());
  known.assign(e.kids.size(), false);
  for (std::size_t i = 0; i < e.kids.size(); ++i) {
    if (has_opaque(e.kids[i])) continue;
    cols[i] = s.evaluate(e.kids[i]);
    known[i] = true;
  }
  return cols;
}

// Folds the known operands other than `skip` with OR (union) or AND (intersection); `found`
// says whether there was any.
Column fold_others(const std::vector<Column>& cols, const std::vector<bool>& known, std::size_t skip,
                   std::size_t from, bool conjunction, bool& found) {
  Column acc;
  found = false;
  for (std::size_t i = from; i < cols.size(); ++i) {
    if (i == skip || !known[i]) continue;
    if (!found) {
      acc = cols[i];
      found = true;
      continue;
    }
    for (std::size_t w = 0; w < acc.size(); ++w) acc[w] = conjunction ? (acc[w] & cols[i][w]) : (acc[w] | cols[i][w]);
  }
  return acc;
}

// Drops operands the rest already decides: a union operand inside the union of the others,
// an intersection operand holding the intersection of the others, a subtrahend that removes
// nothing the others do not. Opaque operands stay, and are left out of the others (which
// makes every removal safe whatever the opaque solid is).
template <std::size_t D>
std::size_t drop_redundant_operands(Expr& e, const SampleSet<D>& s) {
  std::vector<bool> known;
  std::vector<Column> cols = operand_columns(e, s, known);
  const bool difference = e.op == ExprOp::Difference;
  if (difference && !known[0]) return 0;
  std::size_t removed = 0;
  for (std::size_t i = e.kids.size(); i-- > (difference ? 1 : 0);) {
    if (!known[i] || e.kids.size() < 2) continue;
    bool found = false;
    bool redundant = false;
    if (e.op == ExprOp::Union) {
      const Column others = fold_others(cols, known, i, 0, false, found);
      redundant = found && !any_outside(cols[i], others);
    } else if (e.op == ExprOp::Intersection) {
      const Column others = fold_others(cols, known, i, 0, true, found);
      redundant = found && !any_outside(others, cols[i]);
    } else {
      Column cut = fold_others(cols, known, i, 1, false, found);
      Column left = cols[0];
      if (found)
        for (std::size_t w = 0; w < left.size(); ++w) left[w] &= ~cut[w];
      redundant = !any_common(left, cols[i]);
    }
    if (!redundant) continue;
    e.kids.erase(e.kids.begin() + static_cast<std::ptrdiff_t>(i));
    cols.erase(cols.begin() + static_cast<std::ptrdiff_t>(i));
    known.erase(known.begin() + static_cast<std::ptrdiff_t>(i));
    ++removed;
  }
  return removed;
}

template <std::size_t D>
std::size_t sampled_pass(Expr& e, const SampleSet<D>& s) {
  std::size_t n = 0;
  for (Expr& k : e.kids) n += sampled_pass(k, s);
  if (!e.is_operator() || e.op == ExprOp::Complement) return n;
  if (!has_opaque(e) && s.is_empty(e)) {
    e = Expr::empty();
    return n + 1;
  }
  return n + drop_redundant_operands(e, s);
}

template <std::size_t D>
void count_pairs(const Expr& e, const SampleSet<D>& s, std::size_t& pairs, std::size_t& overlapping) {
  for (const Expr& k : e.kids) count_pairs(k, s, pairs, overlapping);
  if (e.kids.size() < 2 || e.op == ExprOp::Complement) return;
  Expr acc = e.kids[0];
  for (std::size_t i = 1; i < e.kids.size(); ++i) {
    if (!has_opaque(acc) && !has_opaque(e.kids[i])) {
      ++pairs;
      overlapping += any_common(s.evaluate(acc), s.evaluate(e.kids[i]));
    }
    acc = Expr::make(e.op, {std::move(acc), e.kids[i]});
  }
}

}  // namespace

template <std::size_t D>
RedundancyReport remove_redundancy(Expr& e, const SampleSet<D>& samples) {
  RedundancyReport report;
  report.structural += apply_structural_rules(e);
  for (int round = 0; round < 32; ++round) {
    const std::size_t n = sampled_pass(e, samples);
    report.sampled += n;
    const std::size_t m = apply_structural_rules(e);
    report.structural += m;
    if (n == 0) break;
  }
  return report;
}

template <std::size_t D>
double proximity(const Expr& e, const SampleSet<D>& samples) {
  std::size_t pairs = 0, overlapping = 0;
  count_pairs(e, samples, pairs, overlapping);
  return pairs == 0 ? 1.0 : static_cast<double>(overlapping) / static_cast<double>(pairs);
}

template RedundancyReport remove_redundancy<2>(Expr&, const SampleSet<2>&);
template RedundancyReport remove_redundancy<3>(Expr&, const SampleSet<3>&);
template double proximity<2>(const Expr&, const SampleSet<2>&);
template double proximity<3>(const Expr&, const SampleSet<3>&);

}  // namespace csgfit::opt
