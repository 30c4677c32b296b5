#include "csgfit/tree3d.h"

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

std::size_t Node3D::primitive_count() const {
  if (is_leaf()) return 1;
  std::size_t n = 0;
  for (const Node3D& c : children) n += c.primitive_count();
  return n;
}

std::size_t Node3D::node_count() const {
  std::size_t n = 1;
  for (const Node3D& c : children) n += c.node_count();
  return n;
}

std::size_t Node3D::depth() const {
  std::size_t d = 0;
  for (const Node3D& c : children) d = std::max(d, c.depth());
  return d + 1;
}

bool Node3D::operator==(const Node3D& o) const {
  if (kind != o.kind) return false;
  if (is_leaf()) return primitive == o.primitive;
  return children == o.children;
}

namespace {

void visit(const Node3D& n, const std::function<void(const Node3D&, std::size_t)>& fn,
           std::size_t& index) {
  fn(n, index++);
  for (const Node3D& c : n.children) visit(c, fn, index);
}

Node3D* find(Node3D& n, std::size_t target, std::size_t& index) {
  if (index++ == target) return &n;
  for (Node3D& c : n.children)
    if (Node3D* hit = find(c, target, index)) return hit;
  return nullptr;
}

template <typename NodeT, typename PrimT>
void collect(NodeT& n, std::vector<PrimT*>& out) {
  if (n.is_leaf()) {
    out.push_back(&n.primitive);
    return;
  }
  for (auto& c : n.children) collect(c, out);
}

// Returns false if `n` is empty after simplification (the rules of simplify(Node&)).
bool simplify_node(Node3D& n) {
  if (n.is_leaf()) return true;
  if (n.kind == NodeKind::Difference) {
    if (n.children.empty() || !simplify_node(n.children.front())) return false;
    std::vector<Node3D> kept;
    kept.push_back(std::move(n.children.front()));
    for (std::size_t i = 1; i < n.children.size(); ++i) {
      Node3D& c = n.children[i];
      if (!simplify_node(c)) continue;
      if (c.kind == NodeKind::Union) {  // a - union(b, c) = a - b - c
        for (Node3D& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    if (kept.front().kind == NodeKind::Difference) {  // (a - b) - c = a - b - c
      Node3D inner = std::move(kept.front());
      std::vector<Node3D> merged = std::move(inner.children);
      for (std::size_t i = 1; i < kept.size(); ++i) merged.push_back(std::move(kept[i]));
      kept = std::move(merged);
    }
    n.children = std::move(kept);
  } else {
    std::vector<Node3D> kept;
    for (Node3D& c : n.children) {
      // An operand that simplified away is gone from the list, not an empty set.
      if (!simplify_node(c)) continue;
      if (c.kind == n.kind) {
        for (Node3D& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    n.children = std::move(kept);
  }
  if (n.children.empty()) return false;
  if (n.children.size() == 1) {
    Node3D only = std::move(n.children.front());
    n = std::move(only);
  }
  return true;
}

void render_into(const Node3D& n, VoxelGrid& out) {
  if (n.is_leaf()) {
    rasterize(n.primitive, out);
    return;
  }
  if (n.children.empty()) {
    out.clear();
    return;
  }
  VoxelGrid child = out;
  render_into(n.children.front(), out);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    render_into(n.children[i], child);
    switch (n.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive: out |= child; break;
      case NodeKind::Difference: out.subtract(child); break;
      case NodeKind::Intersection: out &= child; break;
    }
  }
}

void structure(const Node3D& n, std::string& out) {
  if (n.is_leaf()) {
    out += to_string(n.primitive.kind);
    return;
  }
  out += to_string(n.kind);
  out += '(';
  for (std::size_t i = 0; i < n.children.size(); ++i) {
    if (i) out += ", ";
    structure(n.children[i], out);
  }
  out += ')';
}

}  // namespace

void for_each_node(const Node3D& root,
                   const std::function<void(const Node3D&, std::size_t)>& fn) {
  std::size_t index = 0;
  visit(root, fn, index);
}

Node3D* node_at(Node3D& root, std::size_t preorder_index) {
  std::size_t index = 0;
  return find(root, preorder_index, index);
}

std::vector<Primitive3D*> leaves(Node3D& root) {
  std::vector<Primitive3D*> out;
  collect(root, out);
  return out;
}

std::vector<const Primitive3D*> leaves(const Node3D& root) {
  std::vector<const Primitive3D*> out;
  collect(root, out);
  return out;
}

bool simplify(Node3D& root) { return simplify_node(root); }

VoxelGrid render(const Node3D& root, const VoxelGrid& frame) {
  VoxelGrid out(frame.nx(), frame.ny(), frame.nz(), frame.origin_x(), frame.origin_y(),
                frame.origin_z(), frame.voxel_size());
  render_into(root, out);
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
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    const double c = signed_distance(n.children[i], x, y, z);
    switch (n.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive: d = std::min(d, c); break;
      case NodeKind::Difference: d = std::max(d, -c); break;
      case NodeKind::Intersection: d = std::max(d, c); break;
    }
  }
  return d;
}

std::string structure_string(const Node3D& root) {
  std::string s;
  structure(root, s);
  return s;
}

}  // namespace csgfit
