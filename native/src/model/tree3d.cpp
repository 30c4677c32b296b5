#include "csgfit/model/tree3d.h"

#include "model/tree_walk.h"

#include <algorithm>
#include <limits>

namespace csgfit {

Node3D Node3D::leaf(const Primitive3D& p) {
  Node3D n;
  n.kind = NodeKind::Primitive;
  n.primitive = p;
  return n;
}

Node3D Node3D::op(NodeKind kind, std::vector<Node3D> children) {
  Node3D n;
  n.kind = kind;
  n.children = std::move(children);
  return n;
}

std::size_t Node3D::primitive_count() const { return tree_walk::primitive_count(*this); }
std::size_t Node3D::node_count() const { return tree_walk::node_count(*this); }
std::size_t Node3D::depth() const { return tree_walk::depth(*this); }
bool Node3D::operator==(const Node3D& o) const { return tree_walk::equal(*this, o); }

void for_each_node(const Node3D& root,
                   const std::function<void(const Node3D&, std::size_t)>& fn) {
  std::size_t index = 0;
  tree_walk::visit(root, fn, index);
}

Node3D* node_at(Node3D& root, std::size_t preorder_index) {
  std::size_t index = 0;
  return tree_walk::find(root, preorder_index, index);
}

std::vector<Primitive3D*> leaves(Node3D& root) {
  std::vector<Primitive3D*> out;
  tree_walk::collect(root, out);
  return out;
}

std::vector<const Primitive3D*> leaves(const Node3D& root) {
  std::vector<const Primitive3D*> out;
  tree_walk::collect(root, out);
  return out;
}

bool simplify(Node3D& root) { return tree_walk::simplify(root); }

VoxelGrid render(const Node3D& root, const VoxelGrid& frame) {
  VoxelGrid out(frame.nx(), frame.ny(), frame.nz(), frame.origin_x(), frame.origin_y(),
                frame.origin_z(), frame.voxel_size());
  tree_walk::render_into(root, out);
  return out;
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

std::string structure_string(const Node3D& root) {
  std::string s;
  tree_walk::structure(root, s);
  return s;
}

}  // namespace csgfit
