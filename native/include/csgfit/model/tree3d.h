// The 3D CSG tree: a small value type of 3D primitives under union, difference and
// intersection (the 3D twin of tree.h; same operators, same simplification rules).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// A 3D CSG node. Operators are n-ary as in OpenSCAD: union and intersection of all children,
/// difference = first child minus the union of the others. A value type (copying copies the
/// tree), as Node is.
struct Node3D {
  NodeKind kind = NodeKind::Primitive;
  Primitive3D primitive;         // only for NodeKind::Primitive
  std::vector<Node3D> children;  // only for operators

  static Node3D leaf(const Primitive3D& p);
  static Node3D op(NodeKind kind, std::vector<Node3D> children);

  bool is_leaf() const { return kind == NodeKind::Primitive; }
  /// Number of primitives (leaves) in the subtree.
  std::size_t primitive_count() const;
  /// Number of nodes in the subtree.
  std::size_t node_count() const;
  /// Depth of the subtree (a leaf has depth 1).
  std::size_t depth() const;
  bool operator==(const Node3D& o) const;
  bool operator!=(const Node3D& o) const { return !(*this == o); }
};

/// Visits every node in pre-order; the callback gets the node and its pre-order index.
void for_each_node(const Node3D& root,
                   const std::function<void(const Node3D&, std::size_t)>& fn);
/// The node with the given pre-order index (mutable), or nullptr.
Node3D* node_at(Node3D& root, std::size_t preorder_index);
/// Pointers to all leaves, in pre-order.
std::vector<Primitive3D*> leaves(Node3D& root);
std::vector<const Primitive3D*> leaves(const Node3D& root);

/// The same shape-preserving clean-up as simplify(Node&): single-child operators collapse,
/// nested unions / intersections flatten, (a - b) - c = a - b - c, a - union(b, c) = a - b - c,
/// empty operators go. Returns false if the whole tree became empty.
bool simplify(Node3D& root);

/// Renders the tree on a grid with the placement and size of `frame` (its bits are ignored) by
/// scan-converting every primitive and combining: the simple reference; the search uses
/// TreeEvaluator3D.
VoxelGrid render(const Node3D& root, const VoxelGrid& frame);

/// Whether the point is inside the tree (pointwise, from Primitive3D::contains).
bool contains(const Node3D& root, double x, double y, double z);

/// Signed distance of the tree at a point, composed the usual way: union = min, intersection
/// = max, difference = max(a, -b1, -b2, ...). Negative inside. The sign is exact (it agrees
/// with contains() away from the surface); the magnitude is exact near a single primitive's
/// surface and a lower bound of the true distance elsewhere (as for any min/max composition),
/// which is what surface-sample fitting needs: zero exactly on the tree's surface.
double signed_distance(const Node3D& root, double x, double y, double z);

/// One step of that composition: the distance so far of an operator's first children combined
/// with the next child's.
inline double compose_distance(NodeKind kind, double so_far, double child) {
  switch (kind) {
    case NodeKind::Difference: return so_far > -child ? so_far : -child;
    case NodeKind::Intersection: return so_far > child ? so_far : child;
    case NodeKind::Union:
    case NodeKind::Primitive: break;
  }
  return so_far < child ? so_far : child;
}

/// Rotates every primitive of the tree by q about the origin (centres and orientations).
void rotate_tree(Node3D& tree, const Quaternion& q);

/// A one-line text form for logs and tests, e.g. "difference(box, union(cylinder, sphere))".
std::string structure_string(const Node3D& root);

}  // namespace csgfit
