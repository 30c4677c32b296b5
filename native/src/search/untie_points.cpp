#include "search/untie_points.h"

#include <cmath>
#include <functional>
#include <vector>

namespace csgfit {

namespace {

// A change of one parameter by t; a face move also names its face (local axis, side), whose
// neighbourhood alone it can concern.
struct Move {
  std::function<void(Primitive3D&, double)> apply;
  int axis = -1;
  double side = 0;
};

// A face of a box, rounded box or prism moved alone by t along its local axis `a` (side s): the
// size grows by t and the centre follows by half of it.
Move face(int a, double s) {
  return {[a, s](Primitive3D& p, double t) {
            const Mat3 m = p.rotation.matrix();
            p.dims[static_cast<std::size_t>(a)] += t;
            p.cx += s * 0.5 * t * m[0][a], p.cy += s * 0.5 * t * m[1][a], p.cz += s * 0.5 * t * m[2][a];
          },
          a, s};
}

// The part of the target a move of p by up to `reach` can concern: the points and floor
// samples over or near its bounds, and for a face move near that face's plane (but for the
// top face of a scan from above, which every column under it sees). Whether the move changes
// the fitness shows on them alone (the rest sum to the same), at a fraction of the cost.
PointTarget near_target(const Primitive3D& p, const Move& move, const PointTarget& t, double reach) {
  const Bounds3 b = p.bounds();
  const double margin = reach + 2 * t.spacing;
  // A scan from above measures along the column: any height of it may be concerned.
  const int axes = t.scan == ScanKind::Top ? 2 : 3;
  const Mat3 m = p.rotation.matrix();
  const bool slab = move.axis >= 0 && (t.scan == ScanKind::All || std::fabs(m[2][move.axis]) < 0.1);
  const auto near = [&](const Vec3& q) {
    for (int a = 0; a < axes; ++a)
      if (q[a] < b.lo[a] - margin || q[a] > b.hi[a] + margin) return false;
    if (!slab) return true;
    const Vec3 l = p.to_local(q[0], q[1], q[2]);
    const double plane = move.side * 0.5 * p.dims[static_cast<std::size_t>(move.axis)];
    return std::fabs(l[static_cast<std::size_t>(move.axis)] - plane) <= margin;
  };
  PointTarget out = t;
  out.points.clear(), out.normals.clear(), out.curvature.clear(), out.floor_samples.clear();
  for (std::size_t i = 0; i < t.points.size(); ++i)
    if (near(t.points[i])) {
      out.points.push_back(t.points[i]);
      out.normals.push_back(t.normals[i]);
      out.curvature.push_back(t.curvature[i]);
    }
  for (const Vec3& f : t.floor_samples)
    if (near(f)) out.floor_samples.push_back(f);
  return out;
}

std::vector<Move> moves_of(const Primitive3D& p) {
  std::vector<Move> out;
  if (p.kind == PrimitiveKind3D::Nurbs) return out;  // its net has its own least squares
  if (p.kind == PrimitiveKind3D::Box || p.kind == PrimitiveKind3D::RoundedBox ||
      p.kind == PrimitiveKind3D::TriangularPrism) {
    for (int a = 0; a < 3; ++a)
      for (double s : {1.0, -1.0}) out.push_back(face(a, s));
    if (has_free_corner(p.kind)) out.push_back({[](Primitive3D& q, double t) { q.corner += t; }});
    return out;
  }
  out.push_back({[](Primitive3D& q, double t) { q.cx += t; }});
  out.push_back({[](Primitive3D& q, double t) { q.cy += t; }});
  out.push_back({[](Primitive3D& q, double t) { q.cz += t; }});
  int idx[3];
  const int n = free_dims(p.kind, idx);
  for (int i = 0; i < n; ++i)
    out.push_back({[d = static_cast<std::size_t>(idx[i])](Primitive3D& q, double t) { q.dims[d] += t; }});
  return out;
}

}  // namespace

void untie_against_points(Node3D& tree, FitnessTerms& terms, const PointTarget& target,
                          const FitnessWeights& weights, std::chrono::steady_clock::time_point deadline) {
  const double step = 0.25 * target.spacing, reach = 3 * target.spacing;
  // Only parameters move, never the tree's shape: the leaves stay where they are.
  for (Primitive3D* leaf : leaves(tree)) {
    Primitive3D& p = *leaf;
    for (const Move& move : moves_of(p)) {
      if (std::chrono::steady_clock::now() >= deadline) break;
      const Primitive3D at = p;
      const PointTarget near = near_target(at, move, target, reach);
      if (near.points.empty()) continue;
      const double base = point_fitness(tree, near, weights).fitness;
      const double tol = 1e-12 * std::max(1.0, std::fabs(base));
      const auto same = [&](double t) {
        move.apply(p, t);
        p.normalize();
        const bool flat = point_fitness(tree, near, weights).fitness >= base - tol;
        p = at;
        return flat;
      };
      // How far each way the fitness stays flat: steps out, then bisection of the last one.
      double bound[2] = {0, 0};
      for (int side = 0; side < 2; ++side) {
        const double dir = side == 0 ? 1 : -1;
        double in = 0, out = step;
        while (out <= reach && same(dir * out)) in = out, out += step;
        if (out > reach) { bound[side] = dir * in; continue; }
        for (int k = 0; k < 6; ++k) {
          const double mid = 0.5 * (in + out);
          (same(dir * mid) ? in : out) = mid;
        }
        bound[side] = dir * in;
      }
      // Free both ways (a box's bottom on the table of a scan from above): the points say
      // nothing, and the value the search gave stays.
      if (bound[0] > reach - 1.5 * step && -bound[1] > reach - 1.5 * step) continue;
      // The nearer end is the last row of points; the farther may be only the floor samples,
      // three spacings off. A grid's sample stands for the cell around it: the edge lies half
      // a spacing past the last row, or halfway to a real row beyond it.
      const bool up_nearer = bound[0] < -bound[1];
      const double nearer = up_nearer ? bound[0] : bound[1];
      const double room = 0.5 * (bound[0] - bound[1]);
      const double centre = nearer + (up_nearer ? -1 : 1) * std::min(0.5 * target.spacing, room);
      if (std::fabs(centre) < 1e-9) continue;
      // The steps may have stepped over a narrow dip between the two ends.
      if (!same(centre)) continue;
      move.apply(p, centre);
      p.normalize();
    }
  }
  terms = point_fitness(tree, target, weights);
}

}  // namespace csgfit
