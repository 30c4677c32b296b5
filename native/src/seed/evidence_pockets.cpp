#include "csgfit/seed/evidence_pockets.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
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
    case PrimitiveKind3D::RoundedBox:
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

// Directions to try for a slanted cut, most likely first: the normals of `solid`'s faces, of
// its edges bevelled and its corners chamfered (a machinist's cuts), then 98 spread evenly.
std::vector<Vec3> cut_directions(const Primitive3D& solid) {
  const Mat3 r = solid.rotation.matrix();
  const Vec3 a[3] = {column(r, 0), column(r, 1), column(r, 2)};
  std::vector<Vec3> out;
  for (int i = 0; i < 3; ++i)
    for (double s : {-1.0, 1.0}) out.push_back(scale(a[i], s));
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      for (double si : {-1.0, 1.0})
        for (double sj : {-1.0, 1.0}) out.push_back(normalized(add(scale(a[i], si), scale(a[j], sj))));
  for (double s0 : {-1.0, 1.0})
    for (double s1 : {-1.0, 1.0})
      for (double s2 : {-1.0, 1.0})
        out.push_back(normalized(add(add(scale(a[0], s0), scale(a[1], s1)), scale(a[2], s2))));
  constexpr int kSpread = 98;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < kSpread; ++i) {
    const double z = 1 - (2 * i + 1.0) / kSpread, rho = std::sqrt(1 - z * z);
    out.push_back({rho * std::cos(golden * i), rho * std::sin(golden * i), z});
  }
  return out;
}

// What the cut beyond the plane {x : d.x = level} does inside `solid`: the empty points it
// takes, the seen points (surface deeper than a tolerance, behind) it would erase, the hidden
// ones it gives up.
struct CutEffect {
  int takes = 0, erases = 0, hides = 0;
  double value() const { return takes - 5.0 * erases; }
};

struct PocketEvidence {
  std::vector<Vec3> empty, seen, hidden;  // each inside the solid
};

CutEffect cut_effect(const PocketEvidence& e, const Vec3& d, double level, double tol) {
  CutEffect c;
  for (const Vec3& p : e.empty) c.takes += dot(d, p) >= level;
  for (const Vec3& p : e.seen) c.erases += dot(d, p) > level + tol;
  for (const Vec3& p : e.hidden) c.hides += dot(d, p) > level;
  return c;
}

// The box in a frame whose z is `d`, from the plane at `level` out past every corner of
// `solid`'s local box: all of the solid beyond the plane.
SignedPrimitive cut_beyond(const Primitive3D& solid, const Vec3& d, double level, double beyond) {
  const Mat3 r = solid.rotation.matrix();
  // x along the solid's axis least aligned with d, so that a bevel stays square to its edge.
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(dot(column(r, a), d)) < std::abs(dot(column(r, least), d))) least = a;
  const Vec3 x = normalized(reject(column(r, least), d)), y = cross(d, x);
  const Vec3 half = local_half_extent(solid);
  Vec3 lo{1e300, 1e300, level}, hi{-1e300, -1e300, -1e300};
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 p{solid.cx, solid.cy, solid.cz};
    for (int a = 0; a < 3; ++a) p = add(p, scale(column(r, a), (corner >> a & 1 ? 1 : -1) * half[a]));
    const Vec3 q{dot(x, p), dot(y, p), dot(d, p)};
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], q[a] - beyond), hi[a] = std::max(hi[a], q[a] + beyond);
    hi[2] = std::max(hi[2], q[2] + beyond);
  }
  const Mat3 frame{{{x[0], y[0], d[0]}, {x[1], y[1], d[1]}, {x[2], y[2], d[2]}}};
  const Vec3 c = add(add(scale(x, 0.5 * (lo[0] + hi[0])), scale(y, 0.5 * (lo[1] + hi[1]))),
                     scale(d, 0.5 * (lo[2] + hi[2])));
  SignedPrimitive cut;
  cut.positive = false;
  cut.conjectured = true;
  cut.primitive = Primitive3D::box(c[0], c[1], c[2], hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2],
                                   quaternion_from_matrix(frame));
  return cut;
}

// The plane cut that takes the empty points of `cluster` out of `solid`: over the directions,
// each plane just below the cluster; of those that take at least 90 % of the most (net of what
// they erase), the one that gives up least hidden volume, which the views cannot confirm.
std::optional<SignedPrimitive> slanted_pocket(const Primitive3D& solid, const std::vector<Vec3>& cluster,
                                              const PocketEvidence& e, double tol) {
  struct Option { Vec3 d; double level; CutEffect effect; };
  std::vector<Option> options;
  double best = 0;
  for (const Vec3& d : cut_directions(solid)) {
    double level = 1e300;
    for (const Vec3& p : cluster) level = std::min(level, dot(d, p));
    level -= 0.5 * tol;
    const CutEffect c = cut_effect(e, d, level, tol);
    options.push_back({d, level, c});
    best = std::max(best, c.value());
  }
  const Option* chosen = nullptr;
  for (const Option& o : options)
    if (o.effect.value() >= 0.9 * best && (!chosen || o.effect.hides < chosen->effect.hides)) chosen = &o;
  if (!chosen || best < static_cast<double>(cluster.size()) / 2) return std::nullopt;
  return cut_beyond(solid, chosen->d, chosen->level, 3 * tol);
}

PocketEvidence inside_of(const Primitive3D& solid, const std::vector<Vec3>& empty,
                         const RangeEvidence& evidence) {
  const auto in = [&](const Vec3& p, double margin) { return solid.signed_distance(p[0], p[1], p[2]) < margin; };
  PocketEvidence e;
  for (const Vec3& p : empty)
    if (in(p, 0)) e.empty.push_back(p);
  for (const Vec3& p : evidence.surface)
    if (in(p, evidence.tolerance)) e.seen.push_back(p);
  for (const Vec3& p : evidence.behind)
    if (in(p, 0)) e.seen.push_back(p);
  for (const Vec3& p : evidence.hidden)
    if (in(p, 0)) e.hidden.push_back(p);
  return e;
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
    const PocketEvidence in_node = inside_of(node.primitive, inside, evidence);
    for (const std::vector<int>& c : clusters(in_node.empty, gap)) {
      if (c.size() < min_points) continue;
      std::vector<Vec3> pts;
      for (int i : c) pts.push_back(in_node.empty[i]);
      out.push_back(pocket(node.primitive, pts, 3 * tol, 3 * tol));
      if (auto cut = slanted_pocket(node.primitive, pts, in_node, tol)) out.push_back(std::move(*cut));
    }
  }
  return out;
}

}  // namespace csgfit
