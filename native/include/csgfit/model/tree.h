// The CSG tree: a small value type of primitives under union, difference and intersection.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"

namespace csgfit {

enum class NodeKind { Primitive, Union, Difference, Intersection };

std::string_view to_string(NodeKind kind);

/// A CSG node. Operators are n-ary as in OpenSCAD: union and intersection of all children,
/// difference = first child minus the union of the others. A value type: copying a tree copies
/// it, which is what the search wants (trees are tens of nodes).
struct Node {
  NodeKind kind = NodeKind::Primitive;
  Primitive primitive;          // only for NodeKind::Primitive
  std::vector<Node> children;   // only for operators

  static Node leaf(const Primitive& p);
  static Node op(NodeKind kind, std::vector<Node> children);

  bool is_leaf() const { return kind == NodeKind::Primitive; }
  /// Number of primitives (leaves) in the subtree.
  std::size_t primitive_count() const;
  /// Number of nodes in the subtree.
  std::size_t node_count() const;
  /// Depth of the subtree (a leaf has depth 1).
  std::size_t depth() const;
  bool operator==(const Node& o) const;
  bool operator!=(const Node& o) const { return !(*this == o); }
};

/// Visits every node in pre-order; the callback gets the node and its pre-order index.
void for_each_node(const Node& root, const std::function<void(const Node&, std::size_t)>& fn);
/// The node with the given pre-order index (mutable), or nullptr.
Node* node_at(Node& root, std::size_t preorder_index);
/// Pointers to all leaves, in pre-order.
std::vector<Primitive*> leaves(Node& root);
std::vector<const Primitive*> leaves(const Node& root);

/// Structural clean-up that never changes the shape: operators with one child become that child,
/// nested unions (and nested intersections) are flattened, the subtracted children of nested
/// differences are merged ((a - b) - c = a - b - c), empty operators are removed.
/// Returns false if the whole tree became empty (all leaves removed).
bool simplify(Node& root);

/// Renders the tree by scan-converting every primitive and combining (the reference evaluator:
/// simple and slow; the search uses TreeEvaluator).
Bitmap render(const Node& root, int width, int height);

/// A one-line text form for logs and tests, e.g. "difference(rectangle, union(circle, ...))".
std::string structure_string(const Node& root);

}  // namespace csgfit
