#include "csgfit/optimise/redundancy.h"
#include "stages.h"

namespace csgfit::opt {

template <std::size_t D>
void order_by_proximity(std::vector<Expr>& operands, const SampleSet<D>& s) {
  if (operands.size() < 3 || operands.size() > 256) return;  // quadratic: wide chains keep their order
  std::vector<Column> cols;
  for (const Expr& e : operands) cols.push_back(s.evaluate(e));
  Column acc = cols[0];
  for (std::size_t next = 1; next < operands.size(); ++next) {
    std::size_t pick = next;
    for (std::size_t j = next; j < operands.size(); ++j) {
      if (any_common(acc, cols[j])) {
        pick = j;
        break;
      }
    }
    std::swap(operands[next], operands[pick]);
    std::swap(cols[next], cols[pick]);
    for (std::size_t w = 0; w < acc.size(); ++w) acc[w] |= cols[next][w];
  }
}

template <std::size_t D>
Expr decompose_dominant(Expr e, const SampleSet<D>& s, const RemainingSolver<D>& remaining,
                        OptimizeReport& report) {
  if (!e.is_operator()) return e;
  const Column solid = s.evaluate(e);
  std::vector<Expr> inside, outside;  // halfspaces that dominate the solid / its complement
  for (int h : halfspaces_used(e)) {
    const Column& c = s.column(h);
    if (!any(c)) continue;
    const Expr hs = Expr::halfspace(h);
    if (!any_outside(c, solid) && s.is_empty(Expr::make(ExprOp::Difference, {hs, e}))) inside.push_back(hs);
    else if (!any_common(c, solid) && s.is_empty(Expr::make(ExprOp::Intersection, {hs, e}))) outside.push_back(hs);
  }
  if (inside.empty() && outside.empty()) {
    ++report.remaining_solids;
    return remaining(e, s);
  }
  report.dominant_halfspaces += inside.size() + outside.size();
  Expr rest = std::move(e);
  for (const auto* group : {&inside, &outside})
    for (const Expr& h : *group) substitute(rest, h.index, Expr::empty());
  remove_redundancy(rest, s);
  rest = decompose_dominant(std::move(rest), s, remaining, report);
  std::vector<Expr> united;
  if (rest.op != ExprOp::Empty) united.push_back(std::move(rest));
  for (Expr& h : inside) united.push_back(std::move(h));
  if (united.empty()) return Expr::empty();
  order_by_proximity(united, s);
  Expr result = united.size() == 1 ? std::move(united[0]) : Expr::make(ExprOp::Union, std::move(united));
  if (!outside.empty()) {
    outside.insert(outside.begin(), std::move(result));
    order_by_proximity(outside, s);
    result = Expr::make(ExprOp::Difference, std::move(outside));
  }
  remove_redundancy(result, s);
  return result;
}

template Expr decompose_dominant<2>(Expr, const SampleSet<2>&, const RemainingSolver<2>&, OptimizeReport&);
template Expr decompose_dominant<3>(Expr, const SampleSet<3>&, const RemainingSolver<3>&, OptimizeReport&);
template void order_by_proximity<2>(std::vector<Expr>&, const SampleSet<2>&);
template void order_by_proximity<3>(std::vector<Expr>&, const SampleSet<3>&);

}  // namespace csgfit::opt
