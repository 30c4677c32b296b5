#include "csgfit/search/point_fitness.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "features/point_neighbours.h"

namespace csgfit {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using Spans = std::vector<std::pair<double, double>>;

Spans unite(const Spans& a, const Spans& b) {
  Spans all(a);
  all.insert(all.end(), b.begin(), b.end());
  std::sort(all.begin(), all.end());
  Spans out;
  for (const auto& s : all) {
    if (!out.empty() && s.first <= out.back().second)
      out.back().second = std::max(out.back().second, s.second);
    else
      out.push_back(s);
  }
  return out;
}

Spans intersect(const Spans& a, const Spans& b) {
  Spans out;
  for (const auto& x : a)
    for (const auto& y : b) {
      const double lo = std::max(x.first, y.first), hi = std::min(x.second, y.second);
      if (lo <= hi) out.push_back({lo, hi});
    }
  std::sort(out.begin(), out.end());
  return out;
}

Spans subtract(const Spans& a, const Spans& b) {
  Spans out = a;
  for (const auto& cut : b) {
    Spans next;
    for (const auto& s : out) {
      if (cut.second < s.first || cut.first > s.second) {
        next.push_back(s);
        continue;
      }
      if (s.first < cut.first) next.push_back({s.first, cut.first});
      if (cut.second < s.second) next.push_back({cut.second, s.second});
    }
    out = std::move(next);
  }
  return out;
}

Spans column(const Node3D& n, const Vec3& o) {
  if (n.is_leaf()) {
    double lo[4], hi[4];
    const int k = line_intervals(n.primitive, o, {0, 0, 1}, lo, hi);
    Spans s;
    for (int i = 0; i < k; ++i) s.push_back({lo[i], hi[i]});
    return s;
  }
  Spans s = column(n.children.front(), o);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    const Spans c = column(n.children[i], o);
    if (n.kind == NodeKind::Union) s = unite(s, c);
    else if (n.kind == NodeKind::Intersection) s = intersect(s, c);
    else s = subtract(s, c);
  }
  return s;
}

// Leaves with whether each is subtracted (an odd number of difference cuts above it).
void signed_leaves(const Node3D& n, bool negative, std::vector<std::pair<const Primitive3D*, bool>>& out) {
  if (n.is_leaf()) {
    out.push_back({&n.primitive, negative});
    return;
  }
  for (std::size_t i = 0; i < n.children.size(); ++i)
    signed_leaves(n.children[i], negative != (n.kind == NodeKind::Difference && i > 0), out);
}

// Curvature of a round kind's side versus its flat caps, from the local point.
CurvatureType primitive_curvature(const Primitive3D& p, const Vec3& world) {
  const Vec3 l = p.to_local(world[0], world[1], world[2]);
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::TriangularPrism: return CurvatureType::Flat;
    case PrimitiveKind3D::Sphere:
    case PrimitiveKind3D::Ellipsoid: return CurvatureType::Convex;
    case PrimitiveKind3D::Cylinder:
    case PrimitiveKind3D::Cone: {
      const double side = std::fabs(p.signed_distance(world[0], world[1], world[2]));
      return std::fabs(std::fabs(l[2]) - d[2] / 2) <= side + 1e-9 ? CurvatureType::Flat
                                                                 : CurvatureType::Convex;
    }
    case PrimitiveKind3D::Torus:
      return std::hypot(l[0], l[1]) >= d[0] ? CurvatureType::Convex : CurvatureType::Other;
    case PrimitiveKind3D::RoundedBox: {
      // Convex on the corner arcs (beyond the core in both x and y), unless a cap is nearer.
      const bool arc = std::fabs(l[0]) > d[0] / 2 - p.corner && std::fabs(l[1]) > d[1] / 2 - p.corner;
      const double side = std::fabs(p.signed_distance(world[0], world[1], world[2]));
      return arc && std::fabs(std::fabs(l[2]) - d[2] / 2) > side + 1e-9 ? CurvatureType::Convex
                                                                       : CurvatureType::Flat;
    }
    case PrimitiveKind3D::Nurbs: {
      if (l[2] < 0.5 * std::max(d[2], 1e-12) * 1e-3 || std::fabs(l[0]) >= d[0] / 2 ||
          std::fabs(l[1]) >= d[1] / 2)
        return CurvatureType::Flat;  // floor or walls
      const double h = 0.02 * std::min(d[0], d[1]);
      const Vec3 n0 = p.patch->frame_at(l[0] - h, l[1]).normal, n1 = p.patch->frame_at(l[0] + h, l[1]).normal;
      const Vec3 m0 = p.patch->frame_at(l[0], l[1] - h).normal, m1 = p.patch->frame_at(l[0], l[1] + h).normal;
      const double k = ((n1[0] - n0[0]) + (m1[1] - m0[1])) / (4 * h);
      return classify_curvature(k, 0, d[0] + d[1]);
    }
  }
  return CurvatureType::Other;
}

CurvatureType flipped(CurvatureType c) {
  if (c == CurvatureType::Convex) return CurvatureType::Concave;
  if (c == CurvatureType::Concave) return CurvatureType::Convex;
  return c;
}

Vec3 tree_normal(const Node3D& tree, const Vec3& p, double h) {
  Vec3 g{};
  for (int a = 0; a < 3; ++a) {
    Vec3 q0 = p, q1 = p;
    q0[a] -= h, q1[a] += h;
    g[a] = signed_distance(tree, q1[0], q1[1], q1[2]) - signed_distance(tree, q0[0], q0[1], q0[2]);
  }
  const double n = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(n > 0)) return {0, 0, 0};
  return {g[0] / n, g[1] / n, g[2] / n};
}

}  // namespace

double column_top(const Node3D& tree, double x, double y) {
  const Spans s = column(tree, {x, y, 0});
  return s.empty() ? -kInf : s.back().second;
}

CurvatureType tree_curvature(const Node3D& tree, const Vec3& point) {
  std::vector<std::pair<const Primitive3D*, bool>> leaves;
  signed_leaves(tree, false, leaves);
  double best = kInf;
  CurvatureType out = CurvatureType::Other;
  for (const auto& [p, negative] : leaves) {
    const double d = std::fabs(p->signed_distance(point[0], point[1], point[2]));
    if (d < best) {
      best = d;
      const CurvatureType c = primitive_curvature(*p, point);
      out = negative ? flipped(c) : c;
    }
  }
  return out;
}

PointTarget make_point_target(std::vector<Vec3> points, std::vector<Vec3> normals, ScanKind scan,
                              double floor) {
  if (points.empty() || points.size() != normals.size())
    throw std::invalid_argument("make_point_target: points and normals must match and not be empty");
  PointTarget t;
  t.scan = scan;
  t.floor = floor;
  t.top = floor;
  for (const Vec3& p : points) t.top = std::max(t.top, p[2]);
  const Bounds3 box = bounds_of(points);
  t.diagonal = std::max(std::hypot(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]), 1e-12);
  const features_detail::PointNeighbours grid(points);
  t.spacing = grid.mean_spacing();
  t.curvature = curvature_types(points, normals, t.diagonal);
  if (scan == ScanKind::Top) {
    // The scanner saw the table around the part too: without samples there, a tree could
    // spill past the part's outline for free.
    Bounds3 around = box;
    for (int a = 0; a < 2; ++a) {
      const double m = 0.15 * (box.hi[a] - box.lo[a]) + 3 * t.spacing;
      around.lo[a] -= m, around.hi[a] += m;
    }
    t.floor_samples = grid.empty_floor(around, 3 * t.spacing, floor);
  }
  t.points = std::move(points);
  t.normals = std::move(normals);
  return t;
}

FitnessTerms point_fitness(const Node3D& tree, const PointTarget& t, const FitnessWeights& w,
                           const std::vector<std::size_t>& subset) {
  FitnessTerms f;
  const std::size_t n = subset.empty() ? t.points.size() : subset.size();
  const double scale = w.scale * t.diagonal, h = 0.25 * t.spacing;
  double sum_d = 0, sum_f = 0, sum_n = 0, sum_c = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = subset.empty() ? k : subset[k];
    const Vec3& p = t.points[i];
    double d;
    Vec3 at = p;
    if (t.scan == ScanKind::Top) {
      const double top = column_top(tree, p[0], p[1]);
      d = std::isfinite(top) ? std::fabs(p[2] - top) : p[2] - t.floor;
      if (std::isfinite(top)) at[2] = top;
    } else {
      d = std::fabs(signed_distance(tree, p[0], p[1], p[2]));
    }
    sum_d += d;
    sum_f += 1 / (1 + d / scale);
    const Vec3 m = tree_normal(tree, at, h);
    const Vec3& q = t.normals[i];
    sum_n += std::max(0.0, m[0] * q[0] + m[1] * q[1] + m[2] * q[2]);
    sum_c += tree_curvature(tree, at) == t.curvature[i] ? 1 : 0;
  }
  double sum_floor = 0;
  for (const Vec3& s : t.floor_samples) {
    const double top = column_top(tree, s[0], s[1]);
    sum_floor += 1 / (1 + std::max(0.0, top - t.floor) / scale);
  }
  // A floor sample weighs what a point does in the whole cloud, however small the subset.
  const double wf = static_cast<double>(n) / static_cast<double>(t.points.size());
  const double all = static_cast<double>(n) + wf * static_cast<double>(t.floor_samples.size());
  f.distance = (sum_f + wf * sum_floor) / all;
  f.floor = t.floor_samples.empty() ? 1 : sum_floor / static_cast<double>(t.floor_samples.size());
  f.normals = sum_n / static_cast<double>(n);
  f.curvature = sum_c / static_cast<double>(n);
  f.mean_distance = sum_d / static_cast<double>(n);
  f.nodes = tree.node_count();
  f.fitness = w.distance * f.distance + w.normals * f.normals + w.curvature * f.curvature -
              static_cast<double>(f.nodes) * w.node_cost;
  return f;
}

}  // namespace csgfit
