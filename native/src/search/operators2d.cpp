// The 2D search's perturbations: seed 000's REP, ADD (at the peaks of a distance map), CUT and
// MOD.
#include "search/operators2d.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/optimise/prune.h"
#include "search/operators.h"

namespace csgfit {

using rnd::norm_count;
using rnd::normal;
using rnd::pick;
using rnd::uniform;
using search_ops::Operator;

Candidate2D Operators2D::evaluate(Node tree, const std::vector<Primitive>& fresh, bool pruned) {
  Candidate c;
  if (!simplify(tree)) {
    c.score = std::numeric_limits<double>::infinity();
    return c;
  }
  {
    TreeEvaluator ev(*pb_.target, tree);
    search_ops::optimise_perturbed(ev, fresh, pb_.new_leaf_opt, &pb_.all_leaf_opt);
    evaluations += ev.evaluations();
  }
  if (pruned) prune(tree, *pb_.target, pb_.k);
  return scored(pb_, std::move(tree), evaluations);
}

Candidate2D Operators2D::scored(const Problem2D& pb, Node tree, std::size_t& evaluations) {
  Candidate c;
  c.score = std::numeric_limits<double>::infinity();
  if (tree.primitive_count() == 0) return c;
  TreeEvaluator ev(*pb.target, tree);
  evaluations += ev.evaluations() + tree.primitive_count();
  c.mismatch = ev.mismatch();
  c.primitives = tree.primitive_count();
  c.score = score(c.mismatch, c.primitives, pb.k);
  c.tree = std::move(tree);
  return c;
}

Primitive Operators2D::random_primitive(double cx, double cy, double size) {
  const PrimitiveKind kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
  const double w = std::max(1.0, size), h = std::max(1.0, normal(rng_, size, size / 2));
  const double angle = uniform(rng_, 0, 360);
  switch (kind) {
    case PrimitiveKind::Rectangle: return Primitive::rectangle(cx, cy, w, h, angle);
    case PrimitiveKind::Circle: return Primitive::circle(cx, cy, w / 2);
    case PrimitiveKind::Ellipse: return Primitive::ellipse(cx, cy, w / 2, h / 2, angle);
    case PrimitiveKind::Triangle:
      return Primitive::triangle(cx, cy, w, h, angle, std::round(uniform(rng_, -1, 1)));
  }
  return Primitive::rectangle(cx, cy, w, h, angle);
}

Node Operators2D::random_subtree(int count, std::vector<Primitive>& fresh) {
  const double W = pb_.target->width(), H = pb_.target->height();
  Node tree;
  for (int i = 0; i < count; ++i) {
    const Primitive p = random_primitive(uniform(rng_, W / 4, 3 * W / 4),
                                         uniform(rng_, H / 4, 3 * H / 4),
                                         uniform(rng_, 1, std::min(W, H) / 2));
    fresh.push_back(p);
    if (i == 0) {
      tree = Node::leaf(p);
      continue;
    }
    static const NodeKind ops[3] = {NodeKind::Union, NodeKind::Difference, NodeKind::Intersection};
    tree = Node::op(ops[pick(rng_, 3)], {std::move(tree), Node::leaf(p)});
  }
  return tree;
}

void Operators2D::rep(Node& tree, std::size_t n, std::vector<Primitive>& fresh) {
  Node* at = node_at(tree, pick(rng_, n));
  const int e = static_cast<int>(at->primitive_count());
  *at = random_subtree(norm_count(rng_, e, pb_.params.added_size_sd), fresh);
}

bool Operators2D::added_subtree(bool as_union, Node& added, std::vector<Primitive>& fresh) {
  const std::vector<DistancePeak>& peaks = as_union ? pb_.shape_peaks : pb_.background_peaks;
  if (peaks.empty()) return false;
  const int count = norm_count(rng_, pb_.params.added_size_mean, pb_.params.added_size_sd);
  for (int i = 0; i < count; ++i) {
    // Bigger peaks first, but any of them may be chosen.
    const std::size_t j = std::min(pick(rng_, peaks.size()), pick(rng_, peaks.size()));
    const DistancePeak& pk = peaks[j];
    const double d = pk.distance;
    const Primitive p = random_primitive(pk.x, pk.y, 2 * std::max(1.0, normal(rng_, d, d / 2)));
    fresh.push_back(p);
    added = (i == 0) ? Node::leaf(p) : Node::op(NodeKind::Union, {std::move(added), Node::leaf(p)});
  }
  return true;
}

bool Operators2D::add(Node& tree, std::vector<Primitive>& fresh) {
  if (!pb_.proposals.empty() && rng_() % 4 == 0)
    return search_ops::add_proposal(tree, pb_.proposals, rng_, fresh);
  const bool as_union = rng_() & 1;
  Node added;
  if (!added_subtree(as_union, added, fresh)) return false;
  const std::size_t n = tree.node_count();
  Node* at = (rng_() % 2 == 0) ? &tree : node_at(tree, pick(rng_, n));
  graft(*at, as_union ? NodeKind::Union : NodeKind::Difference, std::move(added));
  return true;
}

Primitive Operators2D::rekinded(Primitive p, PrimitiveKind kind) {
  p.kind = kind;
  if (kind == PrimitiveKind::Triangle) p.apex = std::round(uniform(rng_, -1, 1));
  p.normalize();
  return p;
}

bool Operators2D::mod(Node& tree, std::vector<Primitive>& fresh) {
  std::vector<Primitive*> ls = leaves(tree);
  Primitive* p = ls[pick(rng_, ls.size())];
  if (pb_.kinds.size() < 2) return false;
  PrimitiveKind kind;
  do kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
  while (kind == p->kind);
  *p = rekinded(*p, kind);
  fresh.push_back(*p);
  return true;
}

Candidate2D Operators2D::perturb(const Candidate& parent) {
  Node tree = parent.tree;
  std::vector<Primitive> fresh;
  const Operator op = search_ops::draw_operator(rng_, pb_.params.odds);
  const std::size_t n = tree.node_count();
  bool done = false;
  switch (op) {
    case Operator::Add: done = add(tree, fresh); break;
    case Operator::Cut: done = search_ops::cut(tree, rng_); break;
    case Operator::Mod: done = mod(tree, fresh); break;
    case Operator::Intersect:  // not a 2D operator: REP stands in
    case Operator::Rep: break;
  }
  // REP, also the fallback when another operator had nothing to act on.
  if (!done) rep(tree, n, fresh);
  ++trees;
  return evaluate(std::move(tree), fresh);
}

}  // namespace csgfit
