// Internal to model/: the definitions of tree.h's templates, included by tree2d.cpp and
// tree3d.cpp, which instantiate them for their primitive type (INSTANTIATE_CSG_TREE below).
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/model/tree.h"

namespace csgfit {

namespace tree_walk {

template <typename NodeT>
std::size_t primitive_count(const NodeT& n) {
  if (n.is_leaf()) return 1;
  std::size_t count = 0;
  for (const NodeT& c : n.children) count += primitive_count(c);
  return count;
}

template <typename NodeT>
std::size_t node_count(const NodeT& n) {
  std::size_t count = 1;
  for (const NodeT& c : n.children) count += node_count(c);
  return count;
}

template <typename NodeT>
std::size_t depth(const NodeT& n) {
  std::size_t d = 0;
  for (const NodeT& c : n.children) d = std::max(d, depth(c));
  return d + 1;
}

template <typename NodeT>
bool equal(const NodeT& a, const NodeT& b) {
  if (a.kind != b.kind) return false;
  if (a.is_leaf()) return a.primitive == b.primitive;
  return a.children == b.children;
}

template <typename NodeT>
void visit(const NodeT& n, const std::function<void(const NodeT&, std::size_t)>& fn,
           std::size_t& index) {
  fn(n, index++);
  for (const NodeT& c : n.children) visit(c, fn, index);
}

template <typename NodeT>
NodeT* find(NodeT& n, std::size_t target, std::size_t& index) {
  if (index++ == target) return &n;
  for (NodeT& c : n.children)
    if (NodeT* hit = find(c, target, index)) return hit;
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

/// simplify() of tree.h; returns false if `n` is empty afterwards.
template <typename NodeT>
bool simplify(NodeT& n) {
  if (n.is_leaf()) return true;
  if (n.kind == NodeKind::Difference) {
    if (n.children.empty() || !simplify(n.children.front())) return false;
    std::vector<NodeT> kept;
    kept.push_back(std::move(n.children.front()));
    for (std::size_t i = 1; i < n.children.size(); ++i) {
      NodeT& c = n.children[i];
      if (!simplify(c)) continue;
      if (c.kind == NodeKind::Union) {  // a - union(b, c) = a - b - c
        for (NodeT& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    if (kept.front().kind == NodeKind::Difference) {  // (a - b) - c = a - b - c
      NodeT inner = std::move(kept.front());
      std::vector<NodeT> merged = std::move(inner.children);
      for (std::size_t i = 1; i < kept.size(); ++i) merged.push_back(std::move(kept[i]));
      kept = std::move(merged);
    }
    n.children = std::move(kept);
  } else {
    std::vector<NodeT> kept;
    for (NodeT& c : n.children) {
      // An operand that simplified away is gone from the list (as when pruning removes it),
      // not an empty set: intersection(a, <removed>) is a.
      if (!simplify(c)) continue;
      if (c.kind == n.kind) {
        for (NodeT& g : c.children) kept.push_back(std::move(g));
      } else {
        kept.push_back(std::move(c));
      }
    }
    n.children = std::move(kept);
  }
  if (n.children.empty()) return false;
  if (n.children.size() == 1) {
    NodeT only = std::move(n.children.front());
    n = std::move(only);
  }
  return true;
}

template <typename NodeT>
void structure(const NodeT& n, std::string& out) {
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

/// Rasterises a tree into `out`, which sets the grid's size and placement; works for Bitmap
/// and VoxelGrid alike (the reference evaluator: simple, not fast).
template <typename NodeT, typename GridT>
void render_into(const NodeT& n, GridT& out) {
  if (n.is_leaf()) {
    rasterize(n.primitive, out);
    return;
  }
  if (n.children.empty()) {
    out.clear();
    return;
  }
  GridT child = out;
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

template <typename NodeT>
bool erase_at(NodeT& node, std::size_t target, std::size_t& counter) {
  ++counter;
  for (std::size_t c = 0; c < node.children.size(); ++c) {
    if (counter == target) {
      node.children.erase(node.children.begin() + static_cast<std::ptrdiff_t>(c));
      return true;
    }
    if (erase_at(node.children[c], target, counter)) return true;
  }
  return false;
}

template <typename NodeT, typename PrimT>
bool erase_leaf_below(NodeT& n, const PrimT* leaf) {
  for (std::size_t c = 0; c < n.children.size(); ++c) {
    NodeT& ch = n.children[c];
    if (ch.is_leaf() && &ch.primitive == leaf) {
      if (n.kind == NodeKind::Difference && c == 0)
        n.children.clear();  // the difference loses its base: the whole node goes
      else
        n.children.erase(n.children.begin() + static_cast<std::ptrdiff_t>(c));
      return true;
    }
    if (!ch.is_leaf() && erase_leaf_below(ch, leaf)) return true;
  }
  return false;
}

}  // namespace tree_walk

template <typename P>
bool erase_subtree(CsgNode<P>& root, std::size_t preorder_index) {
  std::size_t counter = 0;
  return tree_walk::erase_at(root, preorder_index, counter);
}

template <typename P>
bool erase_leaf(CsgNode<P>& root, const P* leaf) { return tree_walk::erase_leaf_below(root, leaf); }

template <typename P>
std::size_t CsgNode<P>::primitive_count() const { return tree_walk::primitive_count(*this); }
template <typename P>
std::size_t CsgNode<P>::node_count() const { return tree_walk::node_count(*this); }
template <typename P>
std::size_t CsgNode<P>::depth() const { return tree_walk::depth(*this); }
template <typename P>
bool CsgNode<P>::operator==(const CsgNode& o) const { return tree_walk::equal(*this, o); }

template <typename P>
void for_each_node(
    const CsgNode<P>& root,
    const typename detail::Identity<std::function<void(const CsgNode<P>&, std::size_t)>>::type& fn) {
  std::size_t index = 0;
  tree_walk::visit(root, fn, index);
}

template <typename P>
CsgNode<P>* node_at(CsgNode<P>& root, std::size_t preorder_index) {
  std::size_t index = 0;
  return tree_walk::find(root, preorder_index, index);
}

template <typename P>
std::vector<P*> leaves(CsgNode<P>& root) {
  std::vector<P*> out;
  tree_walk::collect(root, out);
  return out;
}

template <typename P>
std::vector<const P*> leaves(const CsgNode<P>& root) {
  std::vector<const P*> out;
  tree_walk::collect(root, out);
  return out;
}

template <typename P>
bool simplify(CsgNode<P>& root) { return tree_walk::simplify(root); }

template <typename P>
std::string structure_string(const CsgNode<P>& root) {
  std::string s;
  tree_walk::structure(root, s);
  return s;
}

}  // namespace csgfit

// The explicit instantiations of everything above for one primitive type.
#define INSTANTIATE_CSG_TREE(P)                                                              \
  template struct CsgNode<P>;                                                                \
  template void for_each_node<P>(                                                            \
      const CsgNode<P>&,                                                                     \
      const detail::Identity<std::function<void(const CsgNode<P>&, std::size_t)>>::type&);   \
  template CsgNode<P>* node_at<P>(CsgNode<P>&, std::size_t);                                 \
  template std::vector<P*> leaves<P>(CsgNode<P>&);                                           \
  template std::vector<const P*> leaves<P>(const CsgNode<P>&);                               \
  template bool simplify<P>(CsgNode<P>&);                                                    \
  template bool erase_subtree<P>(CsgNode<P>&, std::size_t);                                  \
  template bool erase_leaf<P>(CsgNode<P>&, const P*);                                        \
  template std::string structure_string<P>(const CsgNode<P>&)
