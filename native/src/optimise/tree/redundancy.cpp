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

// The known operands but `skip` (from `from` on), as one operand of `op`.
std::vector<Expr> known_others(const Expr& e, const std::vector<bool>& known, std::size_t skip, std::size_t from) {
  std::vector<Expr> out;
  for (std::size_t i = from; i < e.kids.size(); ++i)
    if (i != skip && known[i]) out.push_back(e.kids[i]);
  return out;
}

// What the columns found, as an empty-set decision on the expression that says it, so that the
// dense check in the operand's own bounds has the last word.
template <std::size_t D>
bool confirmed_redundant(const Expr& e, const std::vector<bool>& known, std::size_t i, const SampleSet<D>& s) {
  if (e.op == ExprOp::Union)
    return s.is_empty(Expr::make(ExprOp::Difference, {e.kids[i], Expr::make(ExprOp::Union, known_others(e, known, i, 0))}));
  if (e.op == ExprOp::Intersection)
    return s.is_empty(
        Expr::make(ExprOp::Difference, {Expr::make(ExprOp::Intersection, known_others(e, known, i, 0)), e.kids[i]}));
  std::vector<Expr> left = known_others(e, known, i, 1);
  left.insert(left.begin(), e.kids[0]);
  return s.is_empty(Expr::make(ExprOp::Intersection, {Expr::make(ExprOp::Difference, std::move(left)), e.kids[i]}));
}

// Drops operands the rest already decides: a union operand inside the union of the others,
// an intersection operand holding the intersection of the others, a subtrahend that removes
// nothing the others do not. Opaque operands stay, and are left out of the others (which
// makes every removal safe whatever the opaque solid is).
template <std::size_t D>
std::size_t drop_redundant_operands(Expr& e, const SampleSet<D>& s) {
  // Each operand is tested against all the others: past this width the exact rules (identical
  // operands) are what a machine-made tree gets, so that the time stays bounded.
  if (e.kids.size() > 256) return 0;
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
    if (!redundant || !confirmed_redundant(e, known, i, s)) continue;
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
  bool acc_known = !has_opaque(e.kids[0]);
  Column acc = acc_known ? s.evaluate(e.kids[0]) : Column();
  for (std::size_t i = 1; i < e.kids.size(); ++i) {
    const bool known = acc_known && !has_opaque(e.kids[i]);
    if (!known) {
      acc_known = false;
      continue;
    }
    const Column c = s.evaluate(e.kids[i]);
    ++pairs;
    overlapping += any_common(acc, c);
    for (std::size_t w = 0; w < acc.size(); ++w)
      acc[w] = e.op == ExprOp::Union ? acc[w] | c[w] : e.op == ExprOp::Intersection ? acc[w] & c[w] : acc[w] & ~c[w];
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
