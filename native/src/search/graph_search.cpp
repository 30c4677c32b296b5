// Best-improvement search over precedence graphs. Every node's signed distance at every sample
// of the evidence is computed once and shared by the graphs that hold it, so that scoring a
// change costs one composition of the tree over the samples.
#include "csgfit/search/graph_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "csgfit/refine/range_refine.h"
#include "csgfit/seed/surface_candidates.h"

namespace csgfit {

namespace {

using Distances = std::shared_ptr<const std::vector<double>>;

// A graph with its nodes' distances and where each node came from (its pool index, or -1).
struct State {
  PrecedenceGraph graph;
  std::vector<Distances> distances;
  std::vector<int> origin;
  double score = std::numeric_limits<double>::infinity();
};

enum class Role { OwnSubobject, BeforeCuts, AfterCuts, CutLast, CutFirst, CutAll, CutWhereItHelps };

// One change: a pool primitive added in a role (node < 0) or put in node's place, or node
// removed (pool < 0).
struct Change {
  int pool = -1, node = -1;
  Role role = Role::OwnSubobject;
  int subobject = -1;
  std::vector<int> targets;  // CutWhereItHelps: the positive nodes it cuts

  static Change add(int pool, Role role, int subobject = -1, std::vector<int> targets = {}) {
    return Change{pool, -1, role, subobject, std::move(targets)};
  }
  static Change replace(int node, int pool) { return Change{pool, node, Role::OwnSubobject, -1, {}}; }
  static Change remove(int node) { return Change{-1, node, Role::OwnSubobject, -1, {}}; }
};

class GraphSearch {
 public:
  GraphSearch(const std::vector<SignedPrimitive>& pool, const RangeEvidence& evidence,
              const GraphSearchOptions& options)
      : pool_(pool), evidence_(evidence), samples_(evidence), options_(options),
        pool_distances_(pool.size()), near_(1.25 * evidence.tolerance),
        nothing_(samples_.size(), std::numeric_limits<double>::infinity()) {}

  State start(PrecedenceGraph graph) {
    State s;
    s.graph = std::move(graph);
    for (const SignedPrimitive& n : s.graph.nodes) s.distances.push_back(distances_of(n.primitive));
    s.origin.assign(s.graph.nodes.size(), -1);
    s.score = score(s);
    return s;
  }

  // One best-improvement step; false when no change pays.
  bool step(State& current) {
    std::vector<std::pair<double, Change>> tried;
    for (const Change& c : changes(current)) {
      State t = apply(current, c);
      if (!t.graph.nodes.empty()) tried.push_back({t.score, c});
      if (out_of_time()) break;
    }
    if (tried.empty()) return false;
    std::stable_sort(tried.begin(), tried.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    State best = current;
    int polished = 0;
    for (const auto& [unpolished, c] : tried) {
      if (c.pool < 0) {  // a removal's score is exact
        if (unpolished < best.score) best = apply(current, c);
        continue;
      }
      if (polished >= options_.polished_per_step || out_of_time()) continue;
      ++polished;
      State t = apply(current, c);
      polish(t, c.node >= 0 ? c.node : static_cast<int>(t.graph.nodes.size()) - 1);
      if (t.score < best.score) best = std::move(t);
    }
    if (!(best.score < current.score - 1e-9 * std::abs(current.score))) return false;
    current = std::move(best);
    return true;
  }

  bool out_of_time() const {
    return std::chrono::steady_clock::now() >= options_.deadline ||
           (options_.cancel && options_.cancel->load());
  }

  std::size_t trials = 0;

 private:
  Distances distances_of(const Primitive3D& p) const {
    auto d = std::make_shared<std::vector<double>>();
    samples_.distances(p, *d);
    return d;
  }

  const Distances& pool_distances(int p) {
    if (!pool_distances_[p]) pool_distances_[p] = distances_of(pool_[p].primitive);
    return pool_distances_[p];
  }

  double score(const State& s) {
    ++trials;
    std::vector<int> leaf_nodes;
    const Node3D tree = precedence_tree(s.graph, &leaf_nodes);
    if (leaf_nodes.empty()) return std::numeric_limits<double>::infinity();
    std::vector<const double*> leaves, kept;
    for (int n : leaf_nodes) {
      leaves.push_back(s.distances[n]->data());
      kept.push_back(s.graph.nodes[n].conjectured ? nothing_.data() : leaves.back());
    }
    const std::size_t n = samples_.size();
    const double* d = composer_.compose(tree, leaves, n).data();
    const double* unconjectured = hidden_composer_.compose_from(tree, kept, n, samples_.hidden_start()).data();
    const Mismatch m = samples_.mismatch(d, unconjectured);
    return static_cast<double>(m.total()) + options_.k * static_cast<double>(leaf_nodes.size());
  }

  // Every change worth scoring: each pool primitive not yet in the graph in each role its sign
  // allows, each node replaced by a pool primitive of its sign, each node removed.
  std::vector<Change> changes(const State& s) {
    std::vector<Change> out;
    const PrecedenceGraph& g = s.graph;
    for (std::size_t p = 0; p < pool_.size(); ++p) {
      if (in_graph(s, static_cast<int>(p))) continue;
      const int pi = static_cast<int>(p);
      if (pool_[p].positive) {
        out.push_back(Change::add(pi, Role::OwnSubobject));
        for (int so = 0; so < g.subobjects; ++so)
          if (has(g, so, [](int order) { return order % 2 == 0; }))
            for (Role r : {Role::BeforeCuts, Role::AfterCuts}) out.push_back(Change::add(pi, r, so));
      } else {
        for (int so = 0; so < g.subobjects; ++so) {
          out.push_back(Change::add(pi, Role::CutLast, so));
          if (has(g, so, [](int order) { return order >= 3 && order % 2 == 1; }))
            out.push_back(Change::add(pi, Role::CutFirst, so));
        }
        if (g.subobjects > 1) out.push_back(Change::add(pi, Role::CutAll));
        std::vector<int> helped = helped_by_cut(s, pi);
        if (!helped.empty()) out.push_back(Change::add(pi, Role::CutWhereItHelps, -1, std::move(helped)));
      }
      for (std::size_t n = 0; n < g.nodes.size(); ++n)
        if (g.nodes[n].positive == pool_[p].positive) out.push_back(Change::replace(static_cast<int>(n), pi));
    }
    for (std::size_t n = 0; n < g.nodes.size(); ++n) out.push_back(Change::remove(static_cast<int>(n)));
    return out;
  }

  // Whether pool primitive p is in the graph already: placed by the search, or read off the
  // surface as the graph's own node.
  bool in_graph(const State& s, int p) const {
    for (std::size_t n = 0; n < s.origin.size(); ++n)
      if (s.origin[n] == p || (s.origin[n] < 0 && alike(s.graph.nodes[n], pool_[p], near_)))
        return true;
    return false;
  }

  // The positive nodes whose score a cut by pool primitive p lowers, each cut alone (a
  // tunnel's hidden lower half and a sphere's, under the plate both stand on, cut by the
  // plate's plane, and the legs under the plate left whole).
  std::vector<int> helped_by_cut(const State& s, int p) {
    std::vector<int> helped;
    for (std::size_t n = 0; n < s.graph.nodes.size(); ++n) {
      if (!s.graph.nodes[n].positive) continue;
      if (apply(s, Change::add(p, Role::CutWhereItHelps, -1, {static_cast<int>(n)})).score < s.score)
        helped.push_back(static_cast<int>(n));
    }
    return helped;
  }

  template <typename Pred>
  static bool has(const PrecedenceGraph& g, int subobject, Pred order_matches) {
    for (std::size_t i = 0; i < g.nodes.size(); ++i)
      if (g.subobject[i] == subobject && order_matches(g.order[i])) return true;
    return false;
  }

  // The arcs that put new node `at` in `role` within subobject `so`.
  static std::vector<PrecedenceArc> arcs_for(const PrecedenceGraph& g, int at, const Change& c) {
    const Role role = c.role;
    const int so = c.subobject;
    std::vector<PrecedenceArc> arcs;
    if (role == Role::CutWhereItHelps) {
      for (int n : c.targets) arcs.push_back({n, at, ArcKind::Subtracting});
      return arcs;
    }
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
      const int n = static_cast<int>(i);
      const bool here = g.subobject[i] == so, positive = g.nodes[i].positive;
      switch (role) {
        case Role::OwnSubobject: break;
        case Role::BeforeCuts:
          if (here && !positive) arcs.push_back({at, n, ArcKind::Subtracting});
          break;
        case Role::AfterCuts:
          if (here && !positive) arcs.push_back({n, at, ArcKind::Appending});
          break;
        case Role::CutLast:
          if (here && positive) arcs.push_back({n, at, ArcKind::Subtracting});
          break;
        case Role::CutFirst:
          if (here && positive && g.order[i] == 1) arcs.push_back({n, at, ArcKind::Subtracting});
          if (here && positive && g.order[i] >= 3) arcs.push_back({at, n, ArcKind::Appending});
          break;
        case Role::CutAll:
          if (positive) arcs.push_back({n, at, ArcKind::Subtracting});
          break;
        case Role::CutWhereItHelps: break;
      }
    }
    return arcs;
  }

  State apply(const State& s, const Change& c) {
    State t;
    if (c.pool < 0) {
      std::vector<int> kept;
      t.graph = without_node(s.graph, c.node, &kept);
      for (int k : kept) t.distances.push_back(s.distances[k]), t.origin.push_back(s.origin[k]);
    } else if (c.node >= 0) {
      t = s;
      t.graph.nodes[c.node].primitive = pool_[c.pool].primitive;
      t.graph.nodes[c.node].open_sides = pool_[c.pool].open_sides;
      t.distances[c.node] = pool_distances(c.pool);
      t.origin[c.node] = c.pool;
    } else {
      const int at = static_cast<int>(s.graph.nodes.size());
      t.graph = with_node(s.graph, pool_[c.pool], arcs_for(s.graph, at, c));
      t.distances = s.distances;
      t.distances.push_back(pool_distances(c.pool));
      t.origin = s.origin;
      t.origin.push_back(c.pool);
    }
    t.score = score(t);
    return t;
  }

  // The pattern search on node `node`'s primitive within the whole tree.
  void polish(State& t, int node) {
    std::vector<int> leaf_nodes;
    Node3D tree = precedence_tree(t.graph, &leaf_nodes);
    const auto at = std::find(leaf_nodes.begin(), leaf_nodes.end(), node);
    if (at == leaf_nodes.end()) return;
    const std::size_t leaf = static_cast<std::size_t>(at - leaf_nodes.begin());
    refine_to_evidence(tree, evidence_, options_.deadline, options_.cancel, {leaf}, kPolishSweeps,
                       conjectured_leaves(t.graph, leaf_nodes));
    t.graph.nodes[node].primitive = *leaves(static_cast<const Node3D&>(tree))[leaf];
    t.distances[node] = distances_of(t.graph.nodes[node].primitive);
    t.score = score(t);
  }

  static constexpr int kPolishSweeps = 12;

  const std::vector<SignedPrimitive>& pool_;
  const RangeEvidence& evidence_;
  const EvidenceSamples samples_;
  const GraphSearchOptions& options_;
  DistanceComposer composer_, hidden_composer_;
  std::vector<Distances> pool_distances_;
  double near_;  // primitives closer than this are one
  const std::vector<double> nothing_;  // the distances of an empty solid
};

}  // namespace

PrecedenceGraph search_graph(PrecedenceGraph graph, const std::vector<SignedPrimitive>& pool,
                             const RangeEvidence& evidence, const GraphSearchOptions& options,
                             GraphSearchStats* stats) {
  GraphSearch search(pool, evidence, options);
  State current = search.start(std::move(graph));
  const double before = current.score;
  std::size_t accepted = 0;
  while (!search.out_of_time() && search.step(current)) ++accepted;
  if (stats) {
    stats->trials = search.trials;
    stats->accepted = accepted;
    stats->score_before = before;
    stats->score_after = current.score;
  }
  return std::move(current.graph);
}

}  // namespace csgfit
