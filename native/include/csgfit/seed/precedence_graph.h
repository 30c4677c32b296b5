// Seed 002's precedence graph: which primitive was added or subtracted before which, from the
// adjacency of their surface patches and inside tests, and the CSG tree it orders.
#pragma once

#include <string>
#include <vector>

#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// A primitive read off the surface patches, with its seed-002 sign.
struct SignedPrimitive {
  Primitive3D primitive;
  bool positive = true;        ///< convex patches give positive primitives, concave negative
  std::vector<int> patches;    ///< the patches it explains
  /// Sides no surface bounds (bit 2 * axis for the local -axis side, 2 * axis + 1 for +axis):
  /// a negative primitive's open ends, reaching through the positive it is subtracted from.
  unsigned open_sides = 0;
  /// A cut no seen surface bounds but the plane it shares with a seen face (a halfspace the
  /// graph search tries): it pays for the hidden material it takes away (range_refine.h).
  bool conjectured = false;
  /// A conjectured cut that is a halfspace through a seen face's plane (not a pocket): what
  /// trims a primitive's hidden part (search/hidden_trim.h).
  bool halfspace = false;
};

enum class ArcKind {
  Subtracting,  ///< the negative primitive is subtracted from the positive one (from -> to)
  Appending     ///< the positive primitive is appended after the negative one (from -> to)
};

struct PrecedenceArc {
  int from = 0, to = 0;        ///< node indices: `from` comes before `to`
  ArcKind kind = ArcKind::Subtracting;
};

/// Nodes are the primitives; arcs say which comes first; each connected digraph is a
/// subobject; order is the topological rank inside it, 1-based (odd = positive).
struct PrecedenceGraph {
  std::vector<SignedPrimitive> nodes;
  std::vector<PrecedenceArc> arcs;
  std::vector<int> subobject;  ///< per node, 0-based
  std::vector<int> order;      ///< per node, 1-based
  int subobjects = 0;
};

/// Builds the graph from primitives and the adjacency of their patches (adjacent[i] lists the
/// nodes whose patches touch node i's): an arc between each adjacent positive / negative pair,
/// subtracting when the negative's patch points lie inside the positive primitive, appending
/// otherwise; then subobjects and orders. `patch_points[i]` are node i's surface points.
PrecedenceGraph build_precedence_graph(std::vector<SignedPrimitive> nodes,
                                       const std::vector<std::vector<int>>& adjacent,
                                       const std::vector<std::vector<Vec3>>& patch_points);

/// The graph without node `node` (and its arcs), orders and subobjects recomputed; cuts left
/// with nothing to cut go too. `kept`, when given, receives the old index of each new node.
PrecedenceGraph without_node(const PrecedenceGraph& graph, int node,
                             std::vector<int>* kept = nullptr);

/// The graph with `node` added as node graph.nodes.size() and `arcs` (node indices of the new
/// graph) added to its own, orders and subobjects recomputed: how the graph search places a
/// primitive (a new subobject, a cut of one, an append after its cuts).
PrecedenceGraph with_node(const PrecedenceGraph& graph, SignedPrimitive node,
                          const std::vector<PrecedenceArc>& arcs);

/// Moves the open sides of a negative primitive (SignedPrimitive::open_sides) out past `target`
/// by `margin`, so that the cut goes through what it cuts and leaves no skin.
void reach_through(SignedPrimitive& cut, const Bounds3& target, double margin);

/// The tree of the graph: per subobject, its primitives applied in order (odd orders added,
/// even subtracted), and the union of the subobjects. `leaf_nodes`, when given, receives the
/// graph node of each leaf in depth-first order.
Node3D precedence_tree(const PrecedenceGraph& graph, std::vector<int>* leaf_nodes = nullptr);

/// Per leaf of precedence_tree(graph, &leaf_nodes): whether it is a conjectured cut.
std::vector<bool> conjectured_leaves(const PrecedenceGraph& graph, const std::vector<int>& leaf_nodes);

/// Seed 002's Fig. 10 listing: subobjects, orders, each primitive with its axes, sizes, sign.
std::string precedence_report(const PrecedenceGraph& graph);

}  // namespace csgfit
