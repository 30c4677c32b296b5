#include "csgfit/tree.h"

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

std::size_t Node::primitive_count() const {
  if (is_leaf()) return 1;
  std::size_t n = 0;
  for (const Node& c : children) n += c.primitive_count();
  return n;
}

std::size_t Node::node_count() const {
  std::size_t n = 1;
  for (const Node& c : children) n += c.node_count();
  return n;
}

std::size_t Node::depth() const {
  std::size_t d = 0;
  for (const Node& c : children) d = std::max(d, c.depth());
  return d + 1;
}

bool Node::operator==(const Node& o) const {
  if (kind != o.kind) return false;
  if (is_leaf()) return primitive == o.primitive;
  return children == o.children;
}

namespace {

void visit(const Node& n, const std::function<void(const Node&, std::size_t)>& fn,
           std::size_t& index) {
  fn(n, index++);
  for (const Node& c : n.children) visit(c, fn, index);
}

Node* find(Node& n, std::size_t target, std::size_t& index) {
  if (index++ == target) return &n;
  for (Node& c : n.children)
    if (Node* hit = find(c, target, index)) return hit;
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

// Returns false if `n` is empty after simplification.
bool simplify_node(Node& n) {
  if (n.is_leaf()) return true;
  if (n.kind == NodeKind::Difference) {
    if (n.children.empty() || !simplify_node(n.children.front())) return false;
    std::vector<Node> kept;
    kept.push_back(std::move(n.children.front()));
    for (std::size_t i = 1; i < n.children.size(); ++i) {
      Node& c = n.children[i];
      if (!simplify_node(c)) continue;
      // a - union(b, c) = a - b - c
      if (c.kind == NodeKind::Union) {
        for (Node& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    // (a - b) - c = a - b - c
    if (kept.front().kind == NodeKind::Difference) {
      Node inner = std::move(kept.front());
      std::vector<Node> merged = std::move(inner.children);
      for (std::size_t i = 1; i < kept.size(); ++i) merged.push_back(std::move(kept[i]));
      kept = std::move(merged);
    }
    n.children = std::move(kept);
  } else {
    std::vector<Node> kept;
    for (Node& c : n.children) {
      // An operand that simplified away is gone from the list (as when pruning removes it),
      // not an empty set: intersection(a, <removed>) is a.
      if (!simplify_node(c)) continue;
      if (c.kind == n.kind) {
        for (Node& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    n.children = std::move(kept);
  }
  if (n.children.empty()) return false;
  if (n.children.size() == 1) {
    Node only = std::move(n.children.front());
    n = std::move(only);
  }
  return true;
}

void render_into(const Node& n, Bitmap& out, Bitmap& scratch) {
  if (n.is_leaf()) {
    rasterize(n.primitive, out);
    return;
  }
  Bitmap child(out.width(), out.height());
  render_into(n.children.front(), out, scratch);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    render_into(n.children[i], child, scratch);
    switch (n.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive: out |= child; break;
      case NodeKind::Difference: out.subtract(child); break;
      case NodeKind::Intersection: out &= child; break;
    }
  }
}

void structure(const Node& n, std::string& out) {
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

void for_each_node(const Node& root, const std::function<void(const Node&, std::size_t)>& fn) {
  std::size_t index = 0;
  visit(root, fn, index);
}

Node* node_at(Node& root, std::size_t preorder_index) {
  std::size_t index = 0;
  return find(root, preorder_index, index);
}

std::vector<Primitive*> leaves(Node& root) {
  std::vector<Primitive*> out;
  collect(root, out);
  return out;
}

std::vector<const Primitive*> leaves(const Node& root) {
  std::vector<const Primitive*> out;
  collect(root, out);
  return out;
}

bool simplify(Node& root) { return simplify_node(root); }

Bitmap render(const Node& root, int width, int height) {
  Bitmap out(width, height);
  Bitmap scratch(width, height);
  render_into(root, out, scratch);
  return out;
}

std::string structure_string(const Node& root) {
  std::string s;
  structure(root, s);
  return s;
}

}  // namespace csgfit
