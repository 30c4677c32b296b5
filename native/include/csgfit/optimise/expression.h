// The optimiser's CSG expression (seed 001, Sec. 3.1): halfspace literals under union,
// intersection, difference and complement, plus the empty and universal sets and opaque
// leaves (geometry we keep verbatim but cannot sample, such as OpenSCAD's hull()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace csgfit::opt {

enum class ExprOp : std::uint8_t {
  Halfspace,     // leaf: halfspace `index`
  Opaque,        // leaf: opaque solid `index`, never sampled, never dropped
  Empty,         // the empty set
  Universe,      // the universal set
  Complement,    // one child
  Union,         // n-ary
  Intersection,  // n-ary
  Difference,    // first child minus the union of the others, as in OpenSCAD
};

/// A node; a small value type like CsgNode (trees are tens to hundreds of nodes).
struct Expr {
  ExprOp op = ExprOp::Empty;
  int index = -1;  // Halfspace and Opaque only
  std::vector<Expr> kids;

  static Expr halfspace(int i) { return {ExprOp::Halfspace, i, {}}; }
  static Expr opaque(int i) { return {ExprOp::Opaque, i, {}}; }
  static Expr empty() { return {ExprOp::Empty, -1, {}}; }
  static Expr universe() { return {ExprOp::Universe, -1, {}}; }
  static Expr complement(Expr e) { return {ExprOp::Complement, -1, {std::move(e)}}; }
  static Expr make(ExprOp op, std::vector<Expr> kids) { return {op, -1, std::move(kids)}; }

  bool is_leaf() const { return op == ExprOp::Halfspace || op == ExprOp::Opaque; }
  bool is_operator() const { return op >= ExprOp::Complement; }
  bool operator==(const Expr& o) const { return op == o.op && index == o.index && kids == o.kids; }
  bool operator!=(const Expr& o) const { return !(*this == o); }
};

/// The seed's size: literals plus operations (every node but the empty/universal constants).
std::size_t expression_size(const Expr& e);
/// Number of halfspace and opaque leaves.
std::size_t literal_count(const Expr& e);
/// Distinct halfspace indices used, ascending.
std::vector<int> halfspaces_used(const Expr& e);
/// Whether an opaque leaf occurs in the subtree (such subtrees are only rewritten by rules
/// that need no geometry).
bool has_opaque(const Expr& e);
/// A structural hash: equal expressions hash alike.
std::uint64_t structural_hash(const Expr& e);
/// Replaces every occurrence of halfspace `index` with `by`.
void substitute(Expr& e, int index, const Expr& by);
/// One-line text form for logs and tests, e.g. "diff(h0, union(h1, h2))".
std::string to_text(const Expr& e);
/// The expression with no Complement nodes left where that is possible: complements become
/// differences (A & ~B = A - B, ~A | B = ~(A - B)); returns false when the root itself is a
/// complement (an unbounded solid), which no bounded CSG tree can write.
bool eliminate_complements(Expr& e);

}  // namespace csgfit::opt
