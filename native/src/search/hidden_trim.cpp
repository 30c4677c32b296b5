// Trims are tried as whole graphs: each node's signed distance at every sample (the evidence's
// and the behind points) is computed once, and a trial composes the tree over them.
#include "csgfit/search/hidden_trim.h"

#include <algorithm>
#include <cstddef>
#include <limits>

#include "csgfit/refine/range_refine.h"

namespace csgfit {

namespace {

constexpr double kSeenSlack = 0.25;     // of the size weight: what a trim may change of the seen
constexpr double kTrimShare = 0.05;     // of the tree's hidden volume: what a trim must take
constexpr double kTargetShare = 0.01;   // ... and what each primitive it cuts must give up

struct Reading {
  double seen = std::numeric_limits<double>::infinity();  // seen mismatch + behind points outside
  std::size_t hidden = 0;                                   // hidden samples inside the tree
};

class TrimScorer {
 public:
  TrimScorer(const RangeEvidence& evidence, const std::vector<SignedPrimitive>& nodes)
      : samples_(evidence), depth_(0.5 * evidence.tolerance) {
    points_ = samples_.points();
    points_.insert(points_.end(), evidence.behind.begin(), evidence.behind.end());
    for (const SignedPrimitive& n : nodes) nodes_.push_back(distances(n.primitive));
  }

  std::vector<double> distances(const Primitive3D& p) const {
    std::vector<double> d(points_.size());
    p.signed_distances(points_.data(), points_.size(), d.data());
    return d;
  }

  // `graph`'s reading, its last node's distances `extra` when the graph has one node more than
  // the scorer knows.
  Reading read(const PrecedenceGraph& graph, const std::vector<double>* extra = nullptr) {
    std::vector<int> leaf_nodes;
    const Node3D tree = precedence_tree(graph, &leaf_nodes);
    if (leaf_nodes.empty()) return {};
    std::vector<const double*> leaves;
    for (int n : leaf_nodes)
      leaves.push_back(static_cast<std::size_t>(n) < nodes_.size() ? nodes_[n].data() : extra->data());
    const std::vector<double>& d = composer_.compose(tree, leaves, points_.size());
    Reading r;
    // The tree itself as the tree without its conjectured cuts: no hidden erasure is priced.
    r.seen = static_cast<double>(samples_.mismatch(d.data(), d.data()).total());
    for (std::size_t s = samples_.size(); s < d.size(); ++s)
      if (d[s] > 0) r.seen += EvidenceSamples::kUnitsPerSample * std::min(1.0, d[s] / depth_);
    for (std::size_t s = samples_.hidden_start(); s < samples_.size(); ++s) r.hidden += d[s] < 0;
    return r;
  }

  void add_node(std::vector<double> d) { nodes_.push_back(std::move(d)); }

 private:
  const EvidenceSamples samples_;
  const double depth_;  // how far behind a return the behind points lie
  std::vector<Vec3> points_;
  std::vector<std::vector<double>> nodes_;
  DistanceComposer composer_;
};

struct Trim {
  PrecedenceGraph graph;
  std::vector<double> cut;  // the new node's distances
  std::size_t erased = 0;
};

PrecedenceGraph cutting(const PrecedenceGraph& g, const SignedPrimitive& cut, const std::vector<int>& targets) {
  const int at = static_cast<int>(g.nodes.size());
  std::vector<PrecedenceArc> arcs;
  for (int t : targets) arcs.push_back({t, at, ArcKind::Subtracting});
  return with_node(g, cut, arcs);
}

// The trim by `cut` of every positive node that gives up hidden volume to it alone unseen; empty
// graph when the trim as a whole does not keep the views or take enough.
Trim trim_by(const PrecedenceGraph& g, const SignedPrimitive& cut, TrimScorer& scorer,
             const Reading& base, double slack) {
  Trim trim;
  trim.cut = scorer.distances(cut.primitive);
  const auto unseen_taking = [&](const PrecedenceGraph& t, double share) {
    const Reading r = scorer.read(t, &trim.cut);
    const bool unseen = r.seen <= base.seen + slack;
    const bool enough = static_cast<double>(r.hidden) <= (1 - share) * static_cast<double>(base.hidden);
    return unseen && enough ? base.hidden - r.hidden : std::size_t{0};
  };
  std::vector<int> targets;
  for (std::size_t n = 0; n < g.nodes.size(); ++n)
    if (g.nodes[n].positive && unseen_taking(cutting(g, cut, {static_cast<int>(n)}), kTargetShare) > 0)
      targets.push_back(static_cast<int>(n));
  if (targets.empty()) return trim;
  PrecedenceGraph t = cutting(g, cut, targets);
  trim.erased = unseen_taking(t, kTrimShare);
  if (trim.erased > 0) trim.graph = std::move(t);
  return trim;
}

}  // namespace

PrecedenceGraph trim_hidden(PrecedenceGraph graph, const std::vector<SignedPrimitive>& pool,
                            const RangeEvidence& evidence, double k, const std::atomic<bool>* cancel) {
  if (evidence.hidden.empty() || graph.nodes.empty()) return graph;
  TrimScorer scorer(evidence, graph.nodes);
  for (;;) {
    const Reading base = scorer.read(graph);
    if (base.hidden == 0) break;
    Trim best;
    for (const SignedPrimitive& cut : pool) {
      if (!cut.halfspace || (cancel && cancel->load())) continue;
      Trim t = trim_by(graph, cut, scorer, base, kSeenSlack * k);
      if (t.erased > best.erased) best = std::move(t);
    }
    if (best.erased == 0) break;
    graph = std::move(best.graph);
    scorer.add_node(std::move(best.cut));
  }
  return graph;
}

}  // namespace csgfit
