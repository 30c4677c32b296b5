#include "csgfit/optimise/inflate.h"

#include "model/random.h"

namespace csgfit::opt {
namespace {

void collect(Expr& e, std::vector<Expr*>& out) {
  out.push_back(&e);
  for (Expr& k : e.kids) collect(k, out);
}

std::vector<Expr*> all_nodes(Expr& e) {
  std::vector<Expr*> out;
  collect(e, out);
  return out;
}

// CSI: n -> n | n or n & n.
void copied_subtree(Expr& n, rnd::Rng& rng) {
  const ExprOp op = rnd::pick(rng, 2) ? ExprOp::Union : ExprOp::Intersection;
  n = Expr::make(op, {n, n});
}

// DNI: n -> ~~n.
void double_negation(Expr& n) { n = Expr::complement(Expr::complement(std::move(n))); }

// DLI at an operator with an operand of the dual kind: X & (Y | Z) -> (X & Y) | (X & Z),
// X | (Y & Z) -> (X | Y) & (X | Z), (Y | Z) - X -> (Y - X) | (Z - X). False when n has no
// such operand.
bool distributive(Expr& n, rnd::Rng& rng) {
  if (n.kids.size() < 2 || n.op == ExprOp::Complement) return false;
  if (n.op == ExprOp::Difference) {
    if (n.kids[0].op != ExprOp::Union) return false;
    std::vector<Expr> parts;
    for (Expr& y : n.kids[0].kids) {
      std::vector<Expr> d{std::move(y)};
      d.insert(d.end(), n.kids.begin() + 1, n.kids.end());
      parts.push_back(Expr::make(ExprOp::Difference, std::move(d)));
    }
    n = Expr::make(ExprOp::Union, std::move(parts));
    return true;
  }
  const ExprOp dual = n.op == ExprOp::Union ? ExprOp::Intersection : ExprOp::Union;
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < n.kids.size(); ++i)
    if (n.kids[i].op == dual && n.kids[i].kids.size() >= 2) candidates.push_back(i);
  if (candidates.empty()) return false;
  const std::size_t at = candidates[rnd::pick(rng, candidates.size())];
  Expr inner = std::move(n.kids[at]);
  n.kids.erase(n.kids.begin() + static_cast<std::ptrdiff_t>(at));
  const Expr x = n.kids.size() == 1 ? n.kids[0] : n;  // the rest of the operands
  std::vector<Expr> parts;
  for (Expr& y : inner.kids) parts.push_back(Expr::make(n.op, {x, std::move(y)}));
  n = Expr::make(dual, std::move(parts));
  return true;
}

// ALI: n -> n | (n & B) or n & (n | B), B a copy of a random subtree of the whole tree.
void absorption(Expr& n, const Expr& b, rnd::Rng& rng) {
  const bool as_union = rnd::pick(rng, 2);
  const ExprOp outer = as_union ? ExprOp::Union : ExprOp::Intersection;
  const ExprOp inner = as_union ? ExprOp::Intersection : ExprOp::Union;
  n = Expr::make(outer, {n, Expr::make(inner, {n, b})});
}

std::size_t pick_strategy(const std::array<double, 4>& w, rnd::Rng& rng) {
  const double total = w[0] + w[1] + w[2] + w[3];
  double r = rnd::uniform(rng, 0, total);
  for (std::size_t i = 0; i < 4; ++i) {
    if (r < w[i]) return i;
    r -= w[i];
  }
  return 3;
}

}  // namespace

Expr inflate(const Expr& tree, const InflateOptions& o, InflateReport* report) {
  rnd::Rng rng(rnd::splitmix(o.seed ^ 0x1f1a7e));
  Expr e = tree;
  if (o.weights[0] + o.weights[1] + o.weights[2] + o.weights[3] <= 0) return e;
  for (std::size_t step = 0; step < o.steps; ++step) {
    Expr next = e;
    std::vector<Expr*> nodes = all_nodes(next);
    const std::size_t kind = pick_strategy(o.weights, rng);
    bool changed = true;
    if (kind == 0) copied_subtree(*nodes[rnd::pick(rng, nodes.size())], rng);
    else if (kind == 1) double_negation(*nodes[rnd::pick(rng, nodes.size())]);
    else if (kind == 3) {
      const Expr b = *nodes[rnd::pick(rng, nodes.size())];
      absorption(*nodes[rnd::pick(rng, nodes.size())], b, rng);
    } else {
      std::vector<Expr*> able;
      for (Expr* n : nodes) {
        Expr probe = *n;
        if (distributive(probe, rng)) able.push_back(n);
      }
      changed = !able.empty() && distributive(*able[rnd::pick(rng, able.size())], rng);
    }
    if (!changed || expression_size(next) > o.max_size) continue;
    e = std::move(next);
    if (report) ++report->applied[kind];
  }
  return e;
}

}  // namespace csgfit::opt
