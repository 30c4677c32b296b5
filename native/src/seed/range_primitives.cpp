#include "csgfit/seed/range_primitives.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/min_quadrilateral_2.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

using PlaneKernel = CGAL::Simple_cartesian<double>;

constexpr double kParallel = 0.97;      // |cos| above which two directions are one
constexpr double kPerpendicular = 0.15; // |cos| below which they are perpendicular

struct Span {
  double lo = 1e300, hi = -1e300;
  void add(double t) { lo = std::min(lo, t); hi = std::max(hi, t); }
  double mid() const { return 0.5 * (lo + hi); }
  double size() const { return hi - lo; }
};

Span span_along(const std::vector<int>& idx, const std::vector<Vec3>& points, const Vec3& origin,
                const Vec3& dir) {
  Span s;
  for (int i : idx) s.add(dot(sub(points[i], origin), dir));
  return s;
}

// The rotation whose local z is `axis`.
Quaternion z_to(const Vec3& axis) {
  const Vec3 z{0, 0, 1};
  const Vec3 c = cross(z, axis);
  const double angle = std::atan2(norm(c), dot(z, axis)) * 180 / M_PI;
  if (norm(c) < 1e-12) return dot(z, axis) > 0 ? Quaternion{} : Quaternion::from_axis_angle(1, 0, 0, 180);
  return Quaternion::from_axis_angle(c[0], c[1], c[2], angle);
}

Quaternion frame_of(const Vec3& e1, const Vec3& e2, const Vec3& e3) {
  Mat3 m;
  for (int r = 0; r < 3; ++r) m[r] = {e1[r], e2[r], e3[r]};
  return quaternion_from_matrix(m);
}

struct Recogniser {
  const std::vector<SurfacePatch>& patches;
  const std::vector<Vec3>& points;
  double diagonal, contact;
  std::vector<std::vector<int>> patch_adjacent;
  std::vector<int> primitive_of_patch;
  RecognisedPrimitives out;

  bool is_plane(int k) const { return patches[k].kind == SurfaceKind::Plane; }

  int add_primitive(SignedPrimitive sp) {
    const int id = static_cast<int>(out.primitives.size());
    for (int k : sp.patches) primitive_of_patch[k] = id;
    out.primitives.push_back(std::move(sp));
    return id;
  }

  // Plane patch `k` is a base of the axial patch `a`: across the axis, within its radius.
  bool is_base(int k, const SurfacePatch& a, double radius) const {
    const SurfacePatch& plane = patches[k];
    if (std::abs(dot(plane.axis, a.axis)) < kParallel) return false;
    std::size_t within = 0;
    for (int i : plane.points)
      within += norm(reject(sub(points[i], a.point), a.axis)) <= radius + contact;
    return 5 * within >= 4 * plane.points.size();
  }

  // The mean position of a patch's points along its axis from its apex (a cone's points lie on
  // the positive side once its axis points into it; CGAL may give either direction).
  double mean_along(const SurfacePatch& s) const {
    double sum = 0;
    for (int i : s.points) sum += dot(sub(points[i], s.point), s.axis);
    return s.points.empty() ? 0.0 : sum / static_cast<double>(s.points.size());
  }

  // `group`: patches of one surface (the largest first), e.g. a hole seen at both its ends.
  void recognise_axial(const std::vector<int>& group) {
    SurfacePatch s = patches[group.front()];
    if (s.kind == SurfaceKind::Cone && mean_along(s) < 0) s.axis = scale(s.axis, -1);
    SignedPrimitive sp;
    sp.positive = s.convex;
    sp.patches = group;
    std::vector<int> idx, neighbours;
    for (int k : group) {
      idx.insert(idx.end(), patches[k].points.begin(), patches[k].points.end());
      neighbours.insert(neighbours.end(), patch_adjacent[k].begin(), patch_adjacent[k].end());
    }
    Span t = span_along(idx, points, s.point, s.axis);
    const double reach = s.kind == SurfaceKind::Cone ? std::max(t.hi, t.lo) * std::tan(s.angle)
                         : s.kind == SurfaceKind::Torus ? s.radius + s.minor_radius : s.radius;
    bool base_lo = false, base_hi = false;
    if (s.kind != SurfaceKind::Torus)
      for (int j : neighbours) {
        if (!is_plane(j) || primitive_of_patch[j] >= 0 || !is_base(j, s, reach)) continue;
        const double at = span_along(patches[j].points, points, s.point, s.axis).mid();
        (std::abs(at - t.lo) < std::abs(at - t.hi) ? base_lo : base_hi) = true;
        sp.patches.push_back(j);
        idx.insert(idx.end(), patches[j].points.begin(), patches[j].points.end());
        t.add(at);
      }
    if (s.kind == SurfaceKind::Cone) {
      // Measured from the apex along the axis into the cone: a frustum between its points.
      t.lo = std::max(0.0, t.lo), t.hi = std::max(t.hi, t.lo + 1e-3 * diagonal);
    }
    const Vec3 centre = add(s.point, scale(s.axis, t.mid()));
    const Quaternion q = z_to(s.axis);
    if (s.kind == SurfaceKind::Cylinder) {
      sp.primitive = Primitive3D::cylinder(centre[0], centre[1], centre[2], s.radius, t.size(), q);
    } else if (s.kind == SurfaceKind::Cone) {
      const double r1 = t.lo * std::tan(s.angle), r2 = t.hi * std::tan(s.angle);
      sp.primitive = Primitive3D::cone(centre[0], centre[1], centre[2], r1, r2, t.size(), q);
    } else {
      sp.primitive = Primitive3D::torus(s.point[0], s.point[1], s.point[2], s.radius,
                                        s.minor_radius, q);
    }
    if (!sp.positive && s.kind != SurfaceKind::Torus)
      sp.open_sides = (base_lo ? 0u : 1u << 4) | (base_hi ? 0u : 1u << 5);
    out.patch_points.push_back(gather(idx));
    add_primitive(std::move(sp));
  }

  std::vector<Vec3> gather(const std::vector<int>& idx) const {
    std::vector<Vec3> v;
    v.reserve(idx.size());
    for (int i : idx) v.push_back(points[i]);
    return v;
  }

  // Seed 002's sign test (Fig. 7): the mean offset of b's points from a's plane along a's
  // normal; negative when b lies behind a (a convex corner).
  double offset(int a, int b) const {
    double sum = 0;
    for (int i : patches[b].points) sum += dot(sub(points[i], patches[a].point), patches[a].axis);
    return sum / static_cast<double>(patches[b].points.size());
  }

  bool perpendicular_neighbours(int a, int b) const {
    return std::abs(dot(patches[a].axis, patches[b].axis)) < kPerpendicular &&
           std::find(patch_adjacent[a].begin(), patch_adjacent[a].end(), b) !=
               patch_adjacent[a].end();
  }

  // Components of the remaining planes under "perpendicular neighbours on a convex (or
  // concave) corner".
  std::vector<std::vector<int>> corner_groups(const std::vector<int>& planes, bool convex) const {
    std::vector<int> parent(planes.size());
    std::iota(parent.begin(), parent.end(), 0);
    const auto find = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (std::size_t i = 0; i < planes.size(); ++i)
      for (std::size_t j = i + 1; j < planes.size(); ++j) {
        const int a = planes[i], b = planes[j];
        if (!perpendicular_neighbours(a, b)) continue;
        const double ab = offset(a, b), ba = offset(b, a);
        if (convex ? (ab < 0 && ba < 0) : (ab > 0 && ba > 0))
          parent[find(static_cast<int>(i))] = find(static_cast<int>(j));
      }
    std::vector<std::vector<int>> groups(planes.size());
    for (std::size_t i = 0; i < planes.size(); ++i)
      groups[find(static_cast<int>(i))].push_back(planes[i]);
    groups.erase(std::remove_if(groups.begin(), groups.end(),
                                [](const std::vector<int>& g) { return g.empty(); }),
                 groups.end());
    return groups;
  }

  // A block from its visible faces: axes from their normals, lengths by projecting their points
  // (Fig. 7(d)); for a negative block, every side no face bounds is open.
  void block_from(const std::vector<int>& group, bool positive) {
    std::vector<int> order = group;
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return patches[a].points.size() > patches[b].points.size(); });
    const Vec3 e1 = patches[order[0]].axis;
    Vec3 e2{0, 0, 0};
    for (int k : order)
      if (std::abs(dot(patches[k].axis, e1)) < kPerpendicular) {
        e2 = normalized(reject(patches[k].axis, e1));
        break;
      }
    if (norm(e2) == 0) e2 = in_plane_axis(order[0], e1);
    const Vec3 e3 = cross(e1, e2);
    std::vector<int> idx;
    for (int k : group) idx.insert(idx.end(), patches[k].points.begin(), patches[k].points.end());
    const Vec3 origin = patches[order[0]].point;
    Span s[3] = {span_along(idx, points, origin, e1), span_along(idx, points, origin, e2),
                 span_along(idx, points, origin, e3)};
    SignedPrimitive sp;
    sp.positive = positive;
    sp.patches = group;
    if (group.size() == 1) extend_slab(order[0], positive, s[0], sp);
    if (!positive && group.size() > 1) sp.open_sides = open_sides_of(group, {e1, e2, e3});
    Vec3 centre = origin;
    for (int a = 0; a < 3; ++a) centre = add(centre, scale(a == 0 ? e1 : a == 1 ? e2 : e3, s[a].mid()));
    const double floor = 1e-3 * diagonal;
    sp.primitive = Primitive3D::box(centre[0], centre[1], centre[2], std::max(floor, s[0].size()),
                                    std::max(floor, s[1].size()), std::max(floor, s[2].size()),
                                    frame_of(e1, e2, e3));
    out.patch_points.push_back(gather(idx));
    add_primitive(std::move(sp));
  }

  // The in-plane axis of a lone face: a side of the smallest rectangle around its points
  // (CGAL's rotating calipers on their convex hull). A face that something in front hides in
  // part keeps its rectangle's directions, where the spread of its points would turn with what
  // hides it (mount's plate behind its boss: 9 degrees off, then too wide to be kept).
  Vec3 in_plane_axis(int k, const Vec3& n) const {
    const Vec3 u = normalized(reject(std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, n));
    const Vec3 w = cross(n, u);
    const Vec3 rectangle_side = min_rectangle_side(patches[k].points, u, w);
    const Vec3 v = normalized(reject(rectangle_side, n));
    return norm(v) > 0 ? v : u;
  }

  // A side of the smallest-area rectangle around the points projected on the plane (u, w).
  Vec3 min_rectangle_side(const std::vector<int>& idx, const Vec3& u, const Vec3& w) const {
    using Point2 = PlaneKernel::Point_2;
    std::vector<Point2> projected, hull;
    projected.reserve(idx.size());
    for (int i : idx) projected.emplace_back(dot(points[i], u), dot(points[i], w));
    CGAL::convex_hull_2(projected.begin(), projected.end(), std::back_inserter(hull));
    if (hull.size() < 3) return u;
    std::vector<Point2> corners;
    CGAL::min_rectangle_2(hull.begin(), hull.end(), std::back_inserter(corners));
    if (corners.size() < 2) return u;
    const double du = corners[1].x() - corners[0].x(), dw = corners[1].y() - corners[0].y();
    return add(scale(u, du), scale(w, dw));
  }

  // A lone face seen with no side: a positive slab reaches as deep behind it as the part does
  // (the smallest block that leaves no seen point in front of a hidden face); a cutting plane
  // (negative) is a halfspace in front of it, open on every other side.
  void extend_slab(int k, bool positive, Span& along_normal, SignedPrimitive& sp) const {
    const SurfacePatch& face = patches[k];
    if (positive) {
      double deepest = 0;
      for (const Vec3& p : points) deepest = std::min(deepest, dot(sub(p, face.point), face.axis));
      along_normal.lo = std::min(along_normal.lo, deepest);
    } else {
      along_normal.hi = along_normal.lo + 0.05 * diagonal;
      sp.open_sides = ~0u & 0x3fu & ~1u;  // bounded only by the face itself (local -x)
    }
  }

  unsigned open_sides_of(const std::vector<int>& group, const std::array<Vec3, 3>& axes) const {
    unsigned closed = 0;
    for (int k : group)
      for (int a = 0; a < 3; ++a) {
        const double c = dot(patches[k].axis, axes[a]);
        // A negative block lies in front of its faces: a face whose normal is +axis bounds
        // the block's -axis side.
        if (c > kParallel) closed |= 1u << (2 * a);
        if (c < -kParallel) closed |= 1u << (2 * a + 1);
      }
    return 0x3fu & ~closed;
  }

  bool inside_some_positive(int k) const {
    std::size_t inside = 0;
    const double tol = 0.01 * diagonal;
    for (int i : patches[k].points)
      for (const SignedPrimitive& sp : out.primitives)
        if (sp.positive && sp.primitive.signed_distance(points[i][0], points[i][1], points[i][2]) < -tol) {
          ++inside;
          break;
        }
    return 2 * inside > patches[k].points.size();
  }

  void recognise_planes() {
    std::vector<int> planes;
    for (std::size_t k = 0; k < patches.size(); ++k)
      if (is_plane(static_cast<int>(k)) && primitive_of_patch[k] < 0) planes.push_back(static_cast<int>(k));
    std::vector<char> grouped(patches.size(), 0);
    for (const auto& g : corner_groups(planes, true))
      if (g.size() > 1) {
        block_from(g, true);
        for (int k : g) grouped[k] = 1;
      }
    // A concave corner is a pocket only where a positive primitive would cover its faces;
    // elsewhere it is where two positive primitives meet.
    for (const auto& g : corner_groups(planes, false))
      if (g.size() > 1 && std::all_of(g.begin(), g.end(), [&](int k) { return inside_some_positive(k); })) {
        block_from(g, false);
        for (int k : g) grouped[k] = 1;
      }
    for (int k : planes)
      if (!grouped[k] && primitive_of_patch[k] < 0) block_from({k}, !inside_some_positive(k));
  }
};

// Whether two curved patches lie on one surface: one kind and sign, centres or axes together,
// radii within a few percent.
bool coincident(const SurfacePatch& a, const SurfacePatch& b, double diagonal) {
  if (a.kind != b.kind || a.convex != b.convex || a.kind == SurfaceKind::Plane) return false;
  const double near = 0.02 * diagonal;
  const auto close = [](double x, double y) { return std::abs(x - y) <= 0.05 * std::max(x, y); };
  switch (a.kind) {
    case SurfaceKind::Sphere: return norm(sub(a.point, b.point)) < near && close(a.radius, b.radius);
    case SurfaceKind::Cylinder:
      return std::abs(dot(a.axis, b.axis)) > 0.99 && norm(reject(sub(b.point, a.point), a.axis)) < near &&
             close(a.radius, b.radius);
    case SurfaceKind::Cone:
      return dot(a.axis, b.axis) > 0.99 && norm(sub(a.point, b.point)) < near && close(a.angle, b.angle);
    case SurfaceKind::Torus:
      return std::abs(dot(a.axis, b.axis)) > 0.99 && norm(sub(a.point, b.point)) < near &&
             close(a.radius, b.radius) && close(a.minor_radius, b.minor_radius);
    case SurfaceKind::Plane: break;
  }
  return false;
}

// Patches grouped by surface, each group's largest patch first (patches come largest first).
std::vector<std::vector<int>> coincident_groups(const std::vector<SurfacePatch>& patches,
                                                double diagonal) {
  std::vector<std::vector<int>> groups;
  std::vector<int> group_of(patches.size(), -1);
  for (std::size_t k = 0; k < patches.size(); ++k) {
    for (std::size_t g = 0; g < groups.size() && group_of[k] < 0; ++g)
      if (coincident(patches[groups[g].front()], patches[k], diagonal)) {
        groups[g].push_back(static_cast<int>(k));
        group_of[k] = static_cast<int>(g);
      }
    if (group_of[k] < 0) {
      group_of[k] = static_cast<int>(groups.size());
      groups.push_back({static_cast<int>(k)});
    }
  }
  return groups;
}

}  // namespace

RecognisedPrimitives recognise_primitives(const std::vector<SurfacePatch>& patches,
                                          const std::vector<Vec3>& points, double diagonal,
                                          double contact) {
  Recogniser r{patches, points, diagonal, contact, patch_adjacency(patches, points, contact),
               std::vector<int>(patches.size(), -1), {}};
  for (const std::vector<int>& group : coincident_groups(patches, diagonal)) {
    const SurfacePatch& s = patches[group.front()];
    if (s.kind == SurfaceKind::Sphere) {
      SignedPrimitive sp;
      sp.primitive = Primitive3D::sphere(s.point[0], s.point[1], s.point[2], s.radius);
      sp.positive = s.convex;
      sp.patches = group;
      std::vector<int> idx;
      for (int k : group) idx.insert(idx.end(), patches[k].points.begin(), patches[k].points.end());
      r.out.patch_points.push_back(r.gather(idx));
      r.add_primitive(std::move(sp));
    } else if (s.kind != SurfaceKind::Plane) {
      r.recognise_axial(group);
    }
  }
  r.recognise_planes();
  // Primitive adjacency from patch adjacency.
  r.out.adjacent.assign(r.out.primitives.size(), {});
  for (std::size_t k = 0; k < patches.size(); ++k)
    for (int j : r.patch_adjacent[k]) {
      const int a = r.primitive_of_patch[k], b = r.primitive_of_patch[j];
      if (a < 0 || b < 0 || a == b) continue;
      auto& list = r.out.adjacent[a];
      if (std::find(list.begin(), list.end(), b) == list.end()) list.push_back(b);
    }
  return std::move(r.out);
}

}  // namespace csgfit
