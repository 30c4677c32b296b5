#include "csgfit/model/tree3d.h"

#include <limits>

#include "model/tree_impl.h"

namespace csgfit {

INSTANTIATE_CSG_TREE(Primitive3D);

VoxelGrid render(const Node3D& root, const VoxelGrid& frame) {
  VoxelGrid out(frame.nx(), frame.ny(), frame.nz(), frame.origin_x(), frame.origin_y(),
                frame.origin_z(), frame.voxel_size());
  tree_walk::render_into(root, out);
  return out;
}

Bounds3 tree_bounds(const Node3D& n) {
  if (n.kind == NodeKind::Primitive) return n.primitive.bounds();
  if (n.children.empty()) return Bounds3{};
  Bounds3 b = tree_bounds(n.children.front());
  if (n.kind == NodeKind::Difference) return b;
  for (std::size_t c = 1; c < n.children.size(); ++c) {
    const Bounds3 e = tree_bounds(n.children[c]);
    for (int a = 0; a < 3; ++a) {
      const bool hull = n.kind == NodeKind::Union;
      b.lo[a] = hull ? std::min(b.lo[a], e.lo[a]) : std::max(b.lo[a], e.lo[a]);
      b.hi[a] = hull ? std::max(b.hi[a], e.hi[a]) : std::min(b.hi[a], e.hi[a]);
    }
  }
  return b;
}

bool contains(const Node3D& n, double x, double y, double z) {
  if (n.is_leaf()) return n.primitive.contains(x, y, z);
  if (n.children.empty()) return false;
  bool v = contains(n.children[0], x, y, z);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    switch (n.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive: v = v || contains(n.children[i], x, y, z); break;
      case NodeKind::Difference: v = v && !contains(n.children[i], x, y, z); break;
      case NodeKind::Intersection: v = v && contains(n.children[i], x, y, z); break;
    }
  }
  return v;
}

double signed_distance(const Node3D& n, double x, double y, double z) {
  if (n.is_leaf()) return n.primitive.signed_distance(x, y, z);
  if (n.children.empty()) return std::numeric_limits<double>::infinity();  // the empty set
  double d = signed_distance(n.children[0], x, y, z);
  for (std::size_t i = 1; i < n.children.size(); ++i)
    d = compose_distance(n.kind, d, signed_distance(n.children[i], x, y, z));
  return d;
}

void rotate_tree(Node3D& tree, const Quaternion& q) {
  if (q.is_identity()) return;
  const Mat3 m = q.matrix();
  for (Primitive3D* p : leaves(tree)) {
    const Vec3 c{m[0][0] * p->cx + m[0][1] * p->cy + m[0][2] * p->cz,
                 m[1][0] * p->cx + m[1][1] * p->cy + m[1][2] * p->cz,
                 m[2][0] * p->cx + m[2][1] * p->cy + m[2][2] * p->cz};
    p->cx = c[0];
    p->cy = c[1];
    p->cz = c[2];
    p->rotation = q * p->rotation;
    p->normalize();
  }
}

}  // namespace csgfit
