#include "csgfit/optimise/tree_expression.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace csgfit::opt {
namespace {

template <typename P>
Expr convert(const CsgNode<P>& n, std::vector<P>& leaves) {
  if (n.is_leaf()) {  // equal primitives are one halfspace, so that copies are identical operands
    const auto at = std::find(leaves.begin(), leaves.end(), n.primitive);
    if (at != leaves.end()) return Expr::halfspace(static_cast<int>(at - leaves.begin()));
    leaves.push_back(n.primitive);
    return Expr::halfspace(static_cast<int>(leaves.size() - 1));
  }
  std::vector<Expr> kids;
  for (const auto& k : n.children) kids.push_back(convert(k, leaves));
  const ExprOp op = n.kind == NodeKind::Union ? ExprOp::Union
                    : n.kind == NodeKind::Intersection ? ExprOp::Intersection
                                                       : ExprOp::Difference;
  return Expr::make(op, std::move(kids));
}

}  // namespace

template <typename P>
Expr expression_of(const CsgNode<P>& tree, std::vector<P>& leaves) {
  leaves.clear();
  return convert(tree, leaves);
}

template <typename P>
CsgNode<P> tree_of(const Expr& e, const std::vector<P>& leaves) {
  switch (e.op) {
    case ExprOp::Halfspace: return CsgNode<P>::leaf(leaves.at(static_cast<std::size_t>(e.index)));
    case ExprOp::Union:
    case ExprOp::Intersection:
    case ExprOp::Difference: {
      std::vector<CsgNode<P>> kids;
      for (const Expr& k : e.kids) kids.push_back(tree_of(k, leaves));
      const NodeKind kind = e.op == ExprOp::Union ? NodeKind::Union
                            : e.op == ExprOp::Intersection ? NodeKind::Intersection
                                                           : NodeKind::Difference;
      return CsgNode<P>::op(kind, std::move(kids));
    }
    default: throw std::logic_error("tree_of: " + to_text(e) + " has no CSG tree form");
  }
}

HalfspaceList<2> halfspaces_of(const std::vector<Primitive>& leaves) {
  HalfspaceList<2> out;
  for (const Primitive& p : leaves) {
    // A box around the shape whatever its angle: its half-diagonal (the apex may lean out).
    const double r = 0.5 * std::hypot(p.w * std::max(1.0, std::abs(p.apex)), p.h) * 1.0001 + 1e-9;
    Halfspace<2> h;
    h.bounds = {{p.cx - r, p.cy - r}, {p.cx + r, p.cy + r}};
    h.contains = [p](const Point<2>& q) { return p.contains(q[0], q[1]); };
    out.push_back(std::move(h));
  }
  return out;
}

HalfspaceList<3> halfspaces_of(const std::vector<Primitive3D>& leaves) {
  HalfspaceList<3> out;
  for (const Primitive3D& p : leaves) {
    Halfspace<3> h;
    const Bounds3 b = p.bounds();
    h.bounds = {{b.lo[0], b.lo[1], b.lo[2]}, {b.hi[0], b.hi[1], b.hi[2]}};
    h.contains = [p](const Point<3>& q) { return p.contains(q[0], q[1], q[2]); };
    out.push_back(std::move(h));
  }
  return out;
}

template <typename P>
CsgNode<P> optimize_csg_tree(const CsgNode<P>& tree, const OptimizeOptions& options, OptimizeReport* report) {
  std::vector<P> leaves;
  const Expr e = expression_of(tree, leaves);
  OptimizeResult r = optimize_tree(e, halfspaces_of(leaves), options);
  if (report) *report = r.report;
  if (r.tree.op == ExprOp::Empty) return tree;
  return tree_of(r.tree, leaves);
}

template Expr expression_of(const CsgNode<Primitive>&, std::vector<Primitive>&);
template Expr expression_of(const CsgNode<Primitive3D>&, std::vector<Primitive3D>&);
template CsgNode<Primitive> tree_of(const Expr&, const std::vector<Primitive>&);
template CsgNode<Primitive3D> tree_of(const Expr&, const std::vector<Primitive3D>&);
template CsgNode<Primitive> optimize_csg_tree(const CsgNode<Primitive>&, const OptimizeOptions&, OptimizeReport*);
template CsgNode<Primitive3D> optimize_csg_tree(const CsgNode<Primitive3D>&, const OptimizeOptions&, OptimizeReport*);

}  // namespace csgfit::opt
