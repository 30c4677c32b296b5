// The CSG tree, written once for 2D and 3D: a small value type of primitives under union,
// difference and intersection. tree2d.h and tree3d.h name the two trees and add what differs.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace csgfit {

enum class NodeKind { Primitive, Union, Difference, Intersection };

std::string_view to_string(NodeKind kind);

/// A CSG node over primitive type P. Operators are n-ary as in OpenSCAD: union and
/// intersection of all children, difference = first child minus the union of the others. A
/// value type: copying a tree copies it, which is what the search wants (trees are tens of
/// nodes); the evaluators work on a separate flat form of it.
template <typename P>
struct CsgNode {
  NodeKind kind = NodeKind::Primitive;
  P primitive;                     // only for NodeKind::Primitive
  std::vector<CsgNode> children;   // only for operators

  static CsgNode leaf(const P& p) {
    CsgNode n;
    n.primitive = p;
    return n;
  }
  static CsgNode op(NodeKind kind, std::vector<CsgNode> children) {
    CsgNode n;
    n.kind = kind;
    n.children = std::move(children);
    return n;
  }

  bool is_leaf() const { return kind == NodeKind::Primitive; }
  /// Number of primitives (leaves) in the subtree.
  std::size_t primitive_count() const;
  /// Number of nodes in the subtree.
  std::size_t node_count() const;
  /// Depth of the subtree (a leaf has depth 1).
  std::size_t depth() const;
  bool operator==(const CsgNode& o) const;
  bool operator!=(const CsgNode& o) const { return !(*this == o); }
};

namespace detail {
// Keeps a parameter out of template argument deduction, so that a lambda converts to the
// std::function a walk takes (std::type_identity is C++20).
template <typename T>
struct Identity {
  using type = T;
};
}  // namespace detail

/// Visits every node in pre-order; the callback gets the node and its pre-order index.
template <typename P>
void for_each_node(
    const CsgNode<P>& root,
    const typename detail::Identity<std::function<void(const CsgNode<P>&, std::size_t)>>::type& fn);
/// The node with the given pre-order index (mutable), or nullptr.
template <typename P>
CsgNode<P>* node_at(CsgNode<P>& root, std::size_t preorder_index);
/// Pointers to all leaves' primitives, in pre-order.
template <typename P>
std::vector<P*> leaves(CsgNode<P>& root);
template <typename P>
std::vector<const P*> leaves(const CsgNode<P>& root);

/// Structural clean-up that never changes the shape: operators with one child become that
/// child, nested unions (and nested intersections) are flattened, (a - b) - c = a - b - c and
/// a - union(b, c) = a - b - c, empty operators are removed. Returns false if the whole tree
/// became empty (all leaves removed).
template <typename P>
bool simplify(CsgNode<P>& root);

/// Removes the subtree with the given pre-order index (> 0: not the root) from its parent;
/// false when there is no such node. What is left may need simplify().
template <typename P>
bool erase_subtree(CsgNode<P>& root, std::size_t preorder_index);

/// Removes the leaf whose primitive is `*leaf` (by address) from its parent; a difference that
/// loses its first operand loses them all. False when the leaf is not in the tree. What is
/// left may need simplify().
template <typename P>
bool erase_leaf(CsgNode<P>& root, const P* leaf);

/// Replaces `at` (a node of some tree) with `kind(old at, subtree)`: how the searches graft a
/// new subtree onto a tree.
template <typename P>
void graft(CsgNode<P>& at, NodeKind kind, CsgNode<P> subtree) {
  CsgNode<P> old = std::move(at);
  at = CsgNode<P>::op(kind, {std::move(old), std::move(subtree)});
}

/// A one-line text form for logs and tests, e.g. "difference(box, union(cylinder, sphere))".
template <typename P>
std::string structure_string(const CsgNode<P>& root);

}  // namespace csgfit
