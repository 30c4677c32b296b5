#include "csgfit/seed/evidence_pockets.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

long long cell_key(long long x, long long y, long long z) {
  return (x * 73856093LL) ^ (y * 19349663LL) ^ (z * 83492791LL);
}

// Groups of points chained by steps shorter than `gap` (a grid of cells of `gap`).
std::vector<std::vector<int>> clusters(const std::vector<Vec3>& pts, double gap) {
  std::vector<int> parent(pts.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto cell = [&](double v) { return static_cast<long long>(std::floor(v / gap)); };
  std::unordered_map<long long, std::vector<int>> grid;
  for (std::size_t i = 0; i < pts.size(); ++i)
    grid[cell_key(cell(pts[i][0]), cell(pts[i][1]), cell(pts[i][2]))].push_back(static_cast<int>(i));
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const long long cx = cell(pts[i][0]), cy = cell(pts[i][1]), cz = cell(pts[i][2]);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(cell_key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if (squared(sub(pts[i], pts[j])) < gap * gap) parent[find(static_cast<int>(i))] = find(j);
        }
  }
  std::unordered_map<int, std::vector<int>> groups;
  for (std::size_t i = 0; i < pts.size(); ++i) groups[find(static_cast<int>(i))].push_back(static_cast<int>(i));
  std::vector<std::vector<int>> out;
  for (auto& [root, members] : groups) out.push_back(std::move(members));
  // Deterministic order, whatever the hash map's: by first member.
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return out;
}

// Half the extent of a primitive's local bounding box along each local axis.
Vec3 local_half_extent(const Primitive3D& p) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::TriangularPrism: return {d[0] / 2, d[1] / 2, d[2] / 2};
    case PrimitiveKind3D::Cylinder: return {d[0], d[0], d[2] / 2};
    case PrimitiveKind3D::Cone: return {std::max(d[0], d[1]), std::max(d[0], d[1]), d[2] / 2};
    case PrimitiveKind3D::Torus: return {d[0] + d[1], d[0] + d[1], d[1]};
    case PrimitiveKind3D::Nurbs: return {d[0] / 2, d[1] / 2, d[2]};
    default: return d;  // sphere, ellipsoid: the semi-axes
  }
}

// The box around `pts` in `solid`'s frame; a side within `near` of the solid's own reaches
// `beyond` past it, so that the cut goes through and leaves no skin.
SignedPrimitive pocket(const Primitive3D& solid, const std::vector<Vec3>& pts, double near,
                       double beyond) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Vec3& p : pts) {
    const Vec3 l = solid.to_local(p[0], p[1], p[2]);
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], l[a]), hi[a] = std::max(hi[a], l[a]);
  }
  const Vec3 half = local_half_extent(solid);
  for (int a = 0; a < 3; ++a) {
    if (hi[a] > half[a] - near) hi[a] = half[a] + beyond;
    if (lo[a] < -half[a] + near) lo[a] = -half[a] - beyond;
  }
  const Mat3 r = solid.rotation.matrix();
  Vec3 centre{solid.cx, solid.cy, solid.cz};
  for (int a = 0; a < 3; ++a) centre = add(centre, scale(column(r, a), 0.5 * (lo[a] + hi[a])));
  SignedPrimitive cut;
  cut.positive = false;
  cut.conjectured = true;
  cut.primitive = Primitive3D::box(centre[0], centre[1], centre[2], hi[0] - lo[0], hi[1] - lo[1],
                                   hi[2] - lo[2], solid.rotation);
  return cut;
}

}  // namespace

std::vector<SignedPrimitive> pocket_proposals(const PrecedenceGraph& graph,
                                              const RangeEvidence& evidence, double gap,
                                              std::size_t min_points) {
  std::vector<SignedPrimitive> out;
  const Node3D tree = precedence_tree(graph);
  if (graph.nodes.empty() || tree.primitive_count() == 0) return out;
  const double tol = evidence.tolerance;
  std::vector<Vec3> inside;
  for (const Vec3& p : evidence.empty)
    if (signed_distance(tree, p[0], p[1], p[2]) < -0.5 * tol) inside.push_back(p);
  if (inside.size() < min_points) return out;
  for (const SignedPrimitive& node : graph.nodes) {
    if (!node.positive) continue;
    std::vector<Vec3> in_node;
    for (const Vec3& p : inside)
      if (node.primitive.signed_distance(p[0], p[1], p[2]) < 0) in_node.push_back(p);
    for (const std::vector<int>& c : clusters(in_node, gap)) {
      if (c.size() < min_points) continue;
      std::vector<Vec3> pts;
      for (int i : c) pts.push_back(in_node[i]);
      out.push_back(pocket(node.primitive, pts, 3 * tol, 3 * tol));
    }
  }
  return out;
}

}  // namespace csgfit
