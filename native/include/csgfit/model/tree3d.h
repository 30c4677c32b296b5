// The 3D CSG tree: boxes, spheres, cylinders, cones, ellipsoids, tori and prisms under union,
// difference and intersection (the tree itself is written once, in tree.h), with what only
// 3D has: pointwise containment, the tree's signed distance, rotation of a whole tree.
#pragma once

#include "csgfit/model/primitive3d.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/model/tree.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

using Node3D = CsgNode<Primitive3D>;

/// Renders the tree on a grid with the placement and size of `frame` (its bits are ignored) by
/// scan-converting every primitive and combining: the simple reference; the search uses
/// TreeEvaluator3D.
VoxelGrid render(const Node3D& root, const VoxelGrid& frame);

/// A box that holds the tree's solid: its primitives' boxes combined as the tree combines them
/// (union: their hull; intersection: their overlap; difference: its first child's). Empty
/// (lo > hi on some axis) when an intersection's boxes do not meet.
Bounds3 tree_bounds(const Node3D& root);

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

}  // namespace csgfit
