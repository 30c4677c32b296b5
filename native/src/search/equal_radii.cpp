// Each member of a group of near-equal radii is tried at the group's median, scored by
// ViewScorer (view_reading.h) against the graph as it came.
#include "csgfit/search/equal_radii.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "model/linalg.h"
#include "view_reading.h"

namespace csgfit {

using namespace linalg;

namespace {

constexpr double kNextRatio = 1.2;    // sorted radii this close to the one before are one group
constexpr double kGroupRatio = 1.5;   // ... and no group spans more
constexpr std::size_t kMinGroup = 3;  // two radii do not say which one is the designer's
constexpr double kSame = 0.005;       // relative: radii this close are equal already

bool is_round(const SignedPrimitive& n) {
  return !n.conjectured &&
         (n.primitive.kind == PrimitiveKind3D::Cylinder || n.primitive.kind == PrimitiveKind3D::Sphere);
}

// The round nodes, grouped by radius (kNextRatio, kGroupRatio, kMinGroup).
std::vector<std::vector<int>> radius_groups(const PrecedenceGraph& g) {
  std::vector<int> order;
  for (std::size_t i = 0; i < g.nodes.size(); ++i)
    if (is_round(g.nodes[i])) order.push_back(static_cast<int>(i));
  const auto r = [&](int i) { return g.nodes[static_cast<std::size_t>(i)].primitive.dims[0]; };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return r(a) < r(b); });
  std::vector<std::vector<int>> groups;
  std::vector<int> group;
  const auto close = [&] {
    if (group.size() >= kMinGroup) groups.push_back(group);
    group.clear();
  };
  for (int i : order) {
    if (!group.empty() && (r(i) > kNextRatio * r(group.back()) || r(i) > kGroupRatio * r(group.front()))) close();
    group.push_back(i);
  }
  close();
  return groups;
}

double median_radius(const PrecedenceGraph& g, const std::vector<int>& group) {
  std::vector<double> r;
  for (int i : group) r.push_back(g.nodes[static_cast<std::size_t>(i)].primitive.dims[0]);
  std::sort(r.begin(), r.end());
  const std::size_t m = r.size() / 2;
  return r.size() % 2 ? r[m] : 0.5 * (r[m - 1] + r[m]);
}

// Unit directions square to a cylinder's axis (eight around it) or around a ball (the six axes
// and the eight diagonals): where the centre may move so that the seen side stays.
std::vector<Vec3> shift_directions(const Primitive3D& p) {
  std::vector<Vec3> out;
  if (p.kind == PrimitiveKind3D::Cylinder) {
    const Mat3 m = p.rotation.matrix();
    const Vec3 u = column(m, 0), v = column(m, 1);
    for (int i = 0; i < 8; ++i) {
      const double a = i * M_PI / 4;
      out.push_back(add(scale(u, std::cos(a)), scale(v, std::sin(a))));
    }
    return out;
  }
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) out.push_back(normalized(Vec3{double(x), double(y), double(z)}));
  return out;
}

}  // namespace

PrecedenceGraph equal_radii(PrecedenceGraph graph, const RangeEvidence& evidence, double k) {
  if (evidence.hidden.empty() || graph.nodes.empty()) return graph;
  ViewScorer scorer(evidence, graph.nodes);
  const double seen = scorer.read(graph).seen;
  for (const std::vector<int>& group : radius_groups(graph)) {
    const double radius = median_radius(graph, group);
    for (int i : group) {
      SignedPrimitive& node = graph.nodes[static_cast<std::size_t>(i)];
      const double change = node.primitive.dims[0] - radius;
      if (std::abs(change) <= kSame * radius) continue;
      Primitive3D best;
      std::vector<double> best_d;
      double best_seen = seen + kSeenSlack * k;
      std::vector<Vec3> shifts = shift_directions(node.primitive);
      shifts.push_back({0, 0, 0});
      for (const Vec3& dir : shifts) {
        Primitive3D trial = node.primitive;
        trial.dims[0] = radius;
        trial.cx += change * dir[0], trial.cy += change * dir[1], trial.cz += change * dir[2];
        std::vector<double> d = scorer.distances(trial);
        const double s = scorer.read(graph, &d, i).seen;
        if (s <= best_seen) best_seen = s, best = trial, best_d = std::move(d);
      }
      if (best_d.empty()) continue;
      node.primitive = best;
      scorer.set_node(i, std::move(best_d));
    }
  }
  return graph;
}

}  // namespace csgfit
