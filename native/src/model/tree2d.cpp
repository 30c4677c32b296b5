#include "csgfit/model/tree.h"

#include "model/tree_walk.h"

#include <algorithm>

namespace csgfit {

std::string_view to_string(NodeKind kind) {
  switch (kind) {
    case NodeKind::Primitive: return "primitive";
    case NodeKind::Union: return "union";
    case NodeKind::Difference: return "difference";
    case NodeKind::Intersection: return "intersection";
  }
  return "?";
}

Node Node::leaf(const Primitive& p) {
  Node n;
  n.kind = NodeKind::Primitive;
  n.primitive = p;
  return n;
}

Node Node::op(NodeKind kind, std::vector<Node> children) {
  Node n;
  n.kind = kind;
  n.children = std::move(children);
  return n;
}

std::size_t Node::primitive_count() const { return tree_walk::primitive_count(*this); }
std::size_t Node::node_count() const { return tree_walk::node_count(*this); }
std::size_t Node::depth() const { return tree_walk::depth(*this); }
bool Node::operator==(const Node& o) const { return tree_walk::equal(*this, o); }

void for_each_node(const Node& root, const std::function<void(const Node&, std::size_t)>& fn) {
  std::size_t index = 0;
  tree_walk::visit(root, fn, index);
}

Node* node_at(Node& root, std::size_t preorder_index) {
  std::size_t index = 0;
  return tree_walk::find(root, preorder_index, index);
}

std::vector<Primitive*> leaves(Node& root) {
  std::vector<Primitive*> out;
  tree_walk::collect(root, out);
  return out;
}

std::vector<const Primitive*> leaves(const Node& root) {
  std::vector<const Primitive*> out;
  tree_walk::collect(root, out);
  return out;
}

bool simplify(Node& root) { return tree_walk::simplify(root); }

Bitmap render(const Node& root, int width, int height) {
  Bitmap out(width, height);
  tree_walk::render_into(root, out);
  return out;
}

std::string structure_string(const Node& root) {
  std::string s;
  tree_walk::structure(root, s);
  return s;
}

}  // namespace csgfit
