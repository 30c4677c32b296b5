#include "csgfit/seed/precedence_graph.h"

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <numeric>
#include <queue>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

// Seed 002, Sec. 4.1: a negative primitive whose surface points lie inside an adjacent positive
// one was subtracted from it; otherwise the positive one was appended after the cut.
double share_inside(const Primitive3D& solid, const std::vector<Vec3>& points, double tol) {
  std::size_t inside = 0;
  for (const Vec3& p : points) inside += solid.signed_distance(p[0], p[1], p[2]) < -tol;
  return points.empty() ? 0.0 : static_cast<double>(inside) / static_cast<double>(points.size());
}

bool mostly_inside(const Primitive3D& positive, const std::vector<Vec3>& points, double tol) {
  return share_inside(positive, points, tol) > 0.5;
}

// Topological ranks, 1-based, each at least one more than its predecessors' and of the parity
// of its sign (odd = positive): Kahn's algorithm; nodes left on a cycle take the first rank of
// their parity.
std::vector<int> ranks(const PrecedenceGraph& g) {
  const std::size_t n = g.nodes.size();
  std::vector<int> indegree(n, 0), order(n, 0);
  std::vector<std::vector<int>> next(n);
  for (const PrecedenceArc& a : g.arcs) next[a.from].push_back(a.to), ++indegree[a.to];
  const auto parity = [&](int node, int at_least) {
    const int want = g.nodes[node].positive ? 1 : 0;
    return (at_least % 2 == want) ? at_least : at_least + 1;
  };
  std::queue<int> ready;
  for (std::size_t i = 0; i < n; ++i)
    if (indegree[i] == 0) ready.push(static_cast<int>(i)), order[i] = parity(static_cast<int>(i), 1);
  while (!ready.empty()) {
    const int u = ready.front();
    ready.pop();
    for (int v : next[u]) {
      order[v] = std::max(order[v], parity(v, order[u] + 1));
      if (--indegree[v] == 0) ready.push(v);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (order[i] == 0) order[i] = parity(static_cast<int>(i), 1);
  return order;
}

std::vector<int> components(const PrecedenceGraph& g, int& count) {
  std::vector<int> parent(g.nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const PrecedenceArc& a : g.arcs) parent[find(a.from)] = find(a.to);
  std::vector<int> id(g.nodes.size(), -1), label(g.nodes.size(), -1);
  count = 0;
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const int root = find(static_cast<int>(i));
    if (label[root] < 0) label[root] = count++;
    id[i] = label[root];
  }
  return id;
}

void reach_open_sides(Primitive3D& cut, unsigned open, const Bounds3& target, double margin) {
  const Mat3 r = cut.rotation.matrix();
  const Vec3 c{cut.cx, cut.cy, cut.cz};
  for (int axis = 0; axis < 3; ++axis) {
    const bool box = cut.kind == PrimitiveKind3D::Box;
    if (!box && !(cut.kind == PrimitiveKind3D::Cylinder && axis == 2)) continue;
    const Vec3 e = column(r, axis);
    double lo = 1e300, hi = -1e300;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? target.hi[0] : target.lo[0], corner & 2 ? target.hi[1] : target.lo[1],
                   corner & 4 ? target.hi[2] : target.lo[2]};
      const double t = dot(sub(p, c), e);
      lo = std::min(lo, t), hi = std::max(hi, t);
    }
    double a = -cut.dims[axis] / 2, b = cut.dims[axis] / 2;
    if (open & (1u << (2 * axis))) a = std::min(a, lo - margin);
    if (open & (1u << (2 * axis + 1))) b = std::max(b, hi + margin);
    cut.dims[axis] = b - a;
    cut.cx += e[0] * (a + b) / 2, cut.cy += e[1] * (a + b) / 2, cut.cz += e[2] * (a + b) / 2;
  }
  cut.normalize();
}

Bounds3 bounds_of(const std::vector<const Primitive3D*>& prims) {
  Bounds3 b = prims.front()->bounds();
  for (const Primitive3D* p : prims) b = merged(b, p->bounds());
  return b;
}

Node3D op_or_leaf(NodeKind kind, std::vector<Node3D> children) {
  if (children.size() == 1) return std::move(children.front());
  return Node3D::op(kind, std::move(children));
}

// One primitive as seed 002's Fig. 10 lists it: kind and sign, axes, sizes, reference point.
std::string describe(std::size_t number, const SignedPrimitive& node) {
  const Primitive3D& p = node.primitive;
  const Mat3 r = p.rotation.matrix();
  char line[200];
  std::string out;
  const auto add = [&](const char* format, auto... values) {
    std::snprintf(line, sizeof line, format, values...);
    out += line;
  };
  std::string kind(to_string(p.kind));
  for (char& c : kind) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  add("Primitive %zu : %s --- %s object%s\n", number, kind.c_str(), node.positive ? "POSITIVE" : "NEGATIVE",
      node.conjectured ? " (a cut through a seen face's plane)" : "");
  if (p.kind == PrimitiveKind3D::Box || p.kind == PrimitiveKind3D::RoundedBox) {
    for (int a = 0; a < 3; ++a)
      add("  %c-axis: (%.6f, %.6f, %.6f)  length: %.6f\n", "XYZ"[a], r[0][a], r[1][a], r[2][a], p.dims[a]);
  } else if (p.kind != PrimitiveKind3D::Sphere) {
    add("  principal axis: (%.6f, %.6f, %.6f)\n", r[0][2], r[1][2], r[2][2]);
  }
  switch (p.kind) {
    case PrimitiveKind3D::Sphere: add("  radius: %.6f\n", p.dims[0]); break;
    case PrimitiveKind3D::Cylinder: add("  radius: %.6f  altitude: %.6f\n", p.dims[0], p.dims[2]); break;
    case PrimitiveKind3D::Cone:
      add("  radii: %.6f, %.6f  altitude: %.6f\n", p.dims[0], p.dims[1], p.dims[2]);
      break;
    case PrimitiveKind3D::Torus: add("  radii: %.6f, %.6f\n", p.dims[0], p.dims[1]); break;
    case PrimitiveKind3D::RoundedBox: add("  corner radius: %.6f\n", p.corner); break;
    default: break;
  }
  add("  reference point: (%.6f, %.6f, %.6f)\n", p.cx, p.cy, p.cz);
  return out;
}

}  // namespace

PrecedenceGraph build_precedence_graph(std::vector<SignedPrimitive> nodes,
                                       const std::vector<std::vector<int>>& adjacent,
                                       const std::vector<std::vector<Vec3>>& patch_points) {
  double size = 0;
  for (const SignedPrimitive& n : nodes)
    for (double d : n.primitive.dims) size = std::max(size, d);
  const double tol = 2e-3 * size;
  // Arcs between adjacent positive / negative pairs.
  std::vector<PrecedenceArc> arcs;
  std::vector<char> cuts(nodes.size(), 0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].positive) continue;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      if (!nodes[j].positive) continue;
      const bool touching = std::find(adjacent[i].begin(), adjacent[i].end(), static_cast<int>(j)) !=
                            adjacent[i].end();
      if (mostly_inside(nodes[j].primitive, patch_points[i], tol)) {
        arcs.push_back({static_cast<int>(j), static_cast<int>(i), ArcKind::Subtracting});
        cuts[i] = 1;
      } else if (touching || share_inside(nodes[i].primitive, patch_points[j], tol) > 0.2) {
        // Beyond the seed's adjacency: a positive primitive seen inside a cut's volume can only
        // have been added after the cut, touching in the image or not (an occluded contact).
        arcs.push_back({static_cast<int>(i), static_cast<int>(j), ArcKind::Appending});
      }
    }
  }
  // A negative primitive that cuts nothing explains no surface the positive ones leave: drop it
  // (and its arcs), renumbering the rest.
  std::vector<int> index(nodes.size(), -1);
  PrecedenceGraph g;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].positive || cuts[i]) index[i] = static_cast<int>(g.nodes.size()), g.nodes.push_back(nodes[i]);
  for (const PrecedenceArc& a : arcs)
    if (index[a.from] >= 0 && index[a.to] >= 0) g.arcs.push_back({index[a.from], index[a.to], a.kind});
  g.order = ranks(g);
  g.subobject = components(g, g.subobjects);
  // Open ends of the cuts reach through what they cut.
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    if (g.nodes[i].positive || g.nodes[i].open_sides == 0) continue;
    std::vector<const Primitive3D*> targets;
    for (const PrecedenceArc& a : g.arcs)
      if (a.to == static_cast<int>(i) && a.kind == ArcKind::Subtracting) targets.push_back(&g.nodes[a.from].primitive);
    if (!targets.empty())
      reach_open_sides(g.nodes[i].primitive, g.nodes[i].open_sides, bounds_of(targets), 0.02 * size);
  }
  return g;
}

void reach_through(SignedPrimitive& cut, const Bounds3& target, double margin) {
  if (!cut.positive && cut.open_sides != 0)
    reach_open_sides(cut.primitive, cut.open_sides, target, margin);
}

PrecedenceGraph with_node(const PrecedenceGraph& graph, SignedPrimitive node,
                          const std::vector<PrecedenceArc>& arcs) {
  PrecedenceGraph g;
  g.nodes = graph.nodes;
  g.nodes.push_back(std::move(node));
  g.arcs = graph.arcs;
  g.arcs.insert(g.arcs.end(), arcs.begin(), arcs.end());
  g.order = ranks(g);
  g.subobject = components(g, g.subobjects);
  return g;
}

PrecedenceGraph without_node(const PrecedenceGraph& graph, int node, std::vector<int>* kept) {
  std::vector<char> keep(graph.nodes.size(), 1);
  keep[node] = 0;
  // A cut whose only subtracting arcs came from the removed node cuts nothing any more.
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    if (graph.nodes[i].positive || !keep[i]) continue;
    bool cuts = false;
    for (const PrecedenceArc& a : graph.arcs)
      cuts |= a.to == static_cast<int>(i) && a.kind == ArcKind::Subtracting && keep[a.from];
    keep[i] = cuts;
  }
  std::vector<int> index(graph.nodes.size(), -1);
  PrecedenceGraph g;
  if (kept) kept->clear();
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    if (!keep[i]) continue;
    index[i] = static_cast<int>(g.nodes.size());
    g.nodes.push_back(graph.nodes[i]);
    if (kept) kept->push_back(static_cast<int>(i));
  }
  for (const PrecedenceArc& a : graph.arcs)
    if (index[a.from] >= 0 && index[a.to] >= 0) g.arcs.push_back({index[a.from], index[a.to], a.kind});
  g.order = ranks(g);
  g.subobject = components(g, g.subobjects);
  return g;
}

Node3D precedence_tree(const PrecedenceGraph& g, std::vector<int>* leaf_nodes) {
  std::vector<Node3D> subobjects;
  std::vector<std::vector<int>> subobject_leaves;
  for (int s = 0; s < g.subobjects; ++s) {
    std::vector<int> members;
    for (std::size_t i = 0; i < g.nodes.size(); ++i)
      if (g.subobject[i] == s) members.push_back(static_cast<int>(i));
    std::sort(members.begin(), members.end(), [&](int a, int b) { return g.order[a] < g.order[b]; });
    // Each level wraps what came before as its first child, so the leaves in depth-first
    // order are the levels' members in order.
    Node3D acc;
    std::vector<int> order_of_leaves;
    bool started = false;
    for (std::size_t at = 0; at < members.size();) {
      const int level = g.order[members[at]];
      std::vector<Node3D> leaves;
      std::vector<int> level_nodes;
      for (; at < members.size() && g.order[members[at]] == level; ++at) {
        leaves.push_back(Node3D::leaf(g.nodes[members[at]].primitive));
        level_nodes.push_back(members[at]);
      }
      const bool positive = level % 2 == 1;
      if (!started && !positive) continue;  // a cut before anything to cut: nothing to do
      order_of_leaves.insert(order_of_leaves.end(), level_nodes.begin(), level_nodes.end());
      if (!started) {
        acc = op_or_leaf(NodeKind::Union, std::move(leaves));
        started = true;
        continue;
      }
      leaves.insert(leaves.begin(), std::move(acc));
      acc = op_or_leaf(positive ? NodeKind::Union : NodeKind::Difference, std::move(leaves));
    }
    if (!started) continue;
    subobjects.push_back(std::move(acc));
    subobject_leaves.push_back(std::move(order_of_leaves));
  }
  if (leaf_nodes) {
    leaf_nodes->clear();
    for (const auto& l : subobject_leaves) leaf_nodes->insert(leaf_nodes->end(), l.begin(), l.end());
  }
  if (subobjects.empty()) return Node3D{};
  return op_or_leaf(NodeKind::Union, std::move(subobjects));
}

std::vector<bool> conjectured_leaves(const PrecedenceGraph& graph, const std::vector<int>& leaf_nodes) {
  std::vector<bool> out;
  for (int n : leaf_nodes) out.push_back(graph.nodes[n].conjectured);
  return out;
}

std::string precedence_report(const PrecedenceGraph& g) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "There are %d subobjects:\n", g.subobjects);
  out += line;
  for (int s = 0; s < g.subobjects; ++s) {
    std::snprintf(line, sizeof line, "----- Subobject %d -----\n", s + 1);
    out += line;
    int top = 0;
    for (std::size_t i = 0; i < g.nodes.size(); ++i)
      if (g.subobject[i] == s) top = std::max(top, g.order[i]);
    for (int o = 1; o <= top; ++o) {
      std::string names;
      for (std::size_t i = 0; i < g.nodes.size(); ++i)
        if (g.subobject[i] == s && g.order[i] == o) names += " " + std::to_string(i + 1);
      if (names.empty()) continue;
      std::snprintf(line, sizeof line, "Order %d primitive%s:%s\n", o, names.size() > 3 ? "s" : "", names.c_str());
      out += line;
    }
  }
  out += "----- PRIMITIVES INFORMATION -----\n";
  for (std::size_t i = 0; i < g.nodes.size(); ++i) out += describe(i + 1, g.nodes[i]);
  return out;
}

}  // namespace csgfit
