#include "csgfit/seed/greedy2d.h"

#include <limits>
#include <stdexcept>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/features/features2d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/seed/decompose2d.h"

namespace csgfit {

namespace {

Primitive placed(PrimitiveKind kind, const DistancePeak& peak) {
  const double d = 2 * std::max(peak.distance, 0.75);
  switch (kind) {
    case PrimitiveKind::Rectangle: return Primitive::rectangle(peak.x, peak.y, d, d, 0);
    case PrimitiveKind::Circle: return Primitive::circle(peak.x, peak.y, d / 2);
    case PrimitiveKind::Ellipse: return Primitive::ellipse(peak.x, peak.y, d / 2, d / 2, 0);
    case PrimitiveKind::Triangle: return Primitive::triangle(peak.x, peak.y, 1.5 * d, 1.5 * d, 0, 0);
  }
  return Primitive::rectangle(peak.x, peak.y, d, d, 0);
}

// The tree with `p` added: unions go next to the other positive pieces, cuts to the root.
Node with_added(const Node& tree, bool has_tree, const Primitive& p, bool as_union) {
  if (!has_tree) return Node::leaf(p);
  if (as_union) {
    if (tree.kind == NodeKind::Difference) {
      Node t = tree;
      Node& base = t.children.front();
      base = base.kind == NodeKind::Union ? base : Node::op(NodeKind::Union, {base});
      base.children.push_back(Node::leaf(p));
      return t;
    }
    if (tree.kind == NodeKind::Union) {
      Node t = tree;
      t.children.push_back(Node::leaf(p));
      return t;
    }
    return Node::op(NodeKind::Union, {tree, Node::leaf(p)});
  }
  if (tree.kind == NodeKind::Difference) {
    Node t = tree;
    t.children.push_back(Node::leaf(p));
    return t;
  }
  return Node::op(NodeKind::Difference, {tree, Node::leaf(p)});
}

}  // namespace

Node greedy_cover(const Bitmap& target, const GreedyOptions& options) {
  if (target.count() == 0) throw std::invalid_argument("no shape found");
  std::vector<PrimitiveKind> kinds;
  for (PrimitiveKind k : {PrimitiveKind::Rectangle, PrimitiveKind::Circle, PrimitiveKind::Ellipse,
                          PrimitiveKind::Triangle})
    if (options.primitives.has(k)) kinds.push_back(k);
  if (kinds.empty()) throw std::invalid_argument("no primitive type allowed");

  LocalOptOptions opt = LocalOptOptions::pattern(40, 2.0, 0.25);
  LocalOptOptions settle = opt;
  settle.max_sweeps = 4;
  settle.initial_step = 0.5;

  Node tree;
  bool has_tree = false;
  double best_score = static_cast<double>(target.count());  // the empty tree
  Bitmap raster(target.width(), target.height());
  for (int step = 0; step < options.max_primitives; ++step) {
    Bitmap uncovered = target;
    uncovered.subtract(raster);
    Bitmap excess = raster;
    excess.subtract(target);
    double step_best = best_score;
    Node step_tree;
    for (bool as_union : {true, false}) {
      const auto peaks = distance_peaks(as_union ? uncovered : excess, 0.5, 1);
      if (peaks.empty()) continue;
      // Candidates: every kind placed at the peak, and seed 003's moment match of the residual
      // piece under the peak (which sees the piece's extent, not only its thickness).
      std::vector<Primitive> starts;
      for (PrimitiveKind kind : kinds) starts.push_back(placed(kind, peaks.front()));
      const Bitmap& residual = as_union ? uncovered : excess;
      const int pc = static_cast<int>(peaks.front().x);
      const int pr = target.height() - 1 - static_cast<int>(peaks.front().y);
      for (Region& piece : connected_regions(residual, 4)) {
        if (!piece.mask.get(pc, pr)) continue;
        if (auto m = match_region(piece.mask, options.primitives)) starts.push_back(m->primitive);
        break;
      }
      for (const Primitive& p : as_union ? options.proposals : options.cut_proposals)
        if (p.contains(peaks.front().x, peaks.front().y)) starts.push_back(p);
      for (const Primitive& fresh : starts) {
        Node trial = with_added(tree, has_tree, fresh, as_union);
        simplify(trial);
        TreeEvaluator ev(target, trial);
        std::size_t fresh_leaf = 0;
        for (std::size_t i = 0; i < ev.leaf_count(); ++i)
          if (ev.leaf(i) == fresh) fresh_leaf = i;
        optimize_leaves(ev, opt, {fresh_leaf});
        optimize_leaves(ev, settle);
        const double s = static_cast<double>(ev.mismatch().total()) +
                         options.k * static_cast<double>(trial.primitive_count());
        if (s < step_best) {
          step_best = s;
          step_tree = trial;
        }
      }
    }
    if (!(step_best < best_score)) break;
    best_score = step_best;
    tree = std::move(step_tree);
    has_tree = true;
    raster = render(tree, target.width(), target.height());
  }
  if (!has_tree) {
    // Even one primitive does not pay for itself: return the best single one anyway.
    const auto peaks = distance_peaks(target, 0.5, 1);
    Node leaf = Node::leaf(placed(kinds.front(), peaks.front()));
    TreeEvaluator ev(target, leaf);
    optimize_leaves(ev, opt);
    return leaf;
  }
  return tree;
}

}  // namespace csgfit
