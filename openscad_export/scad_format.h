// Internal to openscad_export/: what the 2D and 3D .scad writers write the same way.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "csgfit/model/tree.h"

namespace csgfit::scad {

/// Values beyond this are not a drawing any more, and fixed decimals would print hundreds of
/// digits.
inline constexpr double kMaxMagnitude = 1e9;

/// A value with at most `decimals` decimals, trailing zeros removed, never "-0".
std::string number(double v, int decimals);

/// Customizer slider step for a dimension of the given extent (a thousandth of its decade).
double slider_step(double extent);

/// The smallest "nice" number (1, 2 or 5 times a power of ten) that is >= v.
double nice_ceiling(double v);

/// A module name from a source file name: the stem, lower case, non-alphanumerics as '_';
/// `fallback` when nothing is left, prefixed with it when it starts with a digit, suffixed
/// with it when it would shadow an OpenSCAD built-in or one of our helper functions.
std::string identifier(const std::string& source, const std::string& fallback);

/// Control characters replaced: they would end a // comment and inject code.
std::string comment_safe(std::string s);

/// Whether a subtree draws nothing, so the writers can leave it out.
template <typename NodeT>
bool is_empty(const NodeT& n) {
  switch (n.kind) {
    case NodeKind::Primitive: return false;
    case NodeKind::Union:
      return std::all_of(n.children.begin(), n.children.end(), is_empty<NodeT>);
    case NodeKind::Difference: return n.children.empty() || is_empty(n.children.front());
    case NodeKind::Intersection:
      return n.children.empty() ||
             std::any_of(n.children.begin(), n.children.end(), is_empty<NodeT>);
  }
  return true;
}

/// Children of a union (or intersection) with nested nodes of the same kind inlined, except
/// those for which keep_whole(node) holds (a subtree written as one block).
template <typename NodeT, typename KeepWhole>
void collect_flat(const NodeT& n, NodeKind kind, std::vector<const NodeT*>& out,
                  const KeepWhole& keep_whole) {
  for (const NodeT& c : n.children) {
    if (is_empty(c) && kind == NodeKind::Union) continue;
    if (c.kind == kind && !keep_whole(c))
      collect_flat(c, kind, out, keep_whole);
    else
      out.push_back(&c);
  }
}

}  // namespace csgfit::scad
