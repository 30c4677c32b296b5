// How a graph agrees with what the views saw, for the changes tried after the search that must
// leave the seen alone (hidden trims, hidden faces aligned): each node's signed distance at
// every sample (the evidence's and the behind points) is computed once, and a trial composes
// the tree over them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "csgfit/refine/range_refine.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// Of the size weight k: how much a change made after the search (a hidden trim, a cut taken
/// into a block's face, one radius for several) may change what the views see.
constexpr double kSeenSlack = 0.25;

struct Reading {
  double seen = std::numeric_limits<double>::infinity();  // seen mismatch + behind points outside
  std::size_t hidden = 0;                                   // hidden samples inside the tree
};

class ViewScorer {
 public:
  ViewScorer(const RangeEvidence& evidence, const std::vector<SignedPrimitive>& nodes)
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
  // the scorer knows, node `changed`'s `extra` when it is given.
  Reading read(const PrecedenceGraph& graph, const std::vector<double>* extra = nullptr,
               int changed = -1) {
    std::vector<int> leaf_nodes;
    const Node3D tree = precedence_tree(graph, &leaf_nodes);
    if (leaf_nodes.empty()) return {};
    std::vector<const double*> leaves;
    for (int n : leaf_nodes)
      leaves.push_back(n != changed && static_cast<std::size_t>(n) < nodes_.size() ? nodes_[n].data()
                                                                                : extra->data());
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
  void set_node(int n, std::vector<double> d) { nodes_[static_cast<std::size_t>(n)] = std::move(d); }

 private:
  const EvidenceSamples samples_;
  const double depth_;  // how far behind a return the behind points lie
  std::vector<Vec3> points_;
  std::vector<std::vector<double>> nodes_;
  DistanceComposer composer_;
};

}  // namespace csgfit
