// Trims are tried as whole graphs, scored by ViewScorer (view_reading.h).
#include "csgfit/search/hidden_trim.h"

#include <cstddef>

#include "view_reading.h"

namespace csgfit {

namespace {

constexpr double kSeenSlack = 0.25;     // of the size weight: what a trim may change of the seen
constexpr double kTrimShare = 0.05;     // of the tree's hidden volume: what a trim must take
constexpr double kTargetShare = 0.01;   // ... and what each primitive it cuts must give up

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
Trim trim_by(const PrecedenceGraph& g, const SignedPrimitive& cut, ViewScorer& scorer,
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
  ViewScorer scorer(evidence, graph.nodes);
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
