#include "csgfit/model/sweeps.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "model/linalg.h"

namespace csgfit {

namespace {

using linalg::column;
using linalg::cross;
using linalg::dot;
using linalg::norm;
using linalg::reject;
using linalg::scale;
using linalg::sub;

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
// A direction this close to another (in radians) moves a point at the far end of the part by
// about 1e-6 of the part's size: the writers' rounding of lengths.
constexpr double kDirectionTolerance = 1e-6;
constexpr double kLengthTolerance = 1e-6;

bool parallel(const Vec3& a, const Vec3& b) { return norm(cross(a, b)) <= kDirectionTolerance; }

Vec3 centre(const Primitive3D& p) { return {p.cx, p.cy, p.cz}; }

// v in the frame's own coordinates (the columns of `frame` are its axes).
Vec3 in_frame(const Mat3& frame, const Vec3& v) {
  return {dot(column(frame, 0), v), dot(column(frame, 1), v), dot(column(frame, 2), v)};
}

// An operator without children draws nothing: the writers leave it out, so a sweep must not
// hold one (the extent of nothing is not an interval).
bool well_formed(const Node3D& n) {
  return n.is_leaf() ||
         (!n.children.empty() && std::all_of(n.children.begin(), n.children.end(), well_formed));
}

// ---- linear sweeps -------------------------------------------------------------------------

// The local axes along which p is a prism: its section is the same all along them.
std::vector<int> prism_axes(const Primitive3D& p) {
  switch (p.kind) {
    case PrimitiveKind3D::Box: return {0, 1, 2};
    case PrimitiveKind3D::Cylinder:
    case PrimitiveKind3D::TriangularPrism:
    case PrimitiveKind3D::RoundedBox: return {2};
    default: return {};
  }
}

// p's local axis along d (either way), or -1 when p is no prism along d.
int prism_axis_along(const Primitive3D& p, const Vec3& d) {
  const Mat3 m = p.rotation.matrix();
  for (int k : prism_axes(p))
    if (parallel(column(m, k), d)) return k;
  return -1;
}

struct Span {
  double lo = 0, hi = 0;
};

Span leaf_span(const Primitive3D& p, int axis, const Vec3& d) {
  const double c = dot(centre(p), d);
  return {c - p.dims[axis] / 2, c + p.dims[axis] / 2};
}

// Where along d the subtree can be: a union is within the hull of its children, an
// intersection within their overlap, a difference within its first child. Nothing when a leaf
// is no prism along d.
std::optional<Span> extent(const Node3D& n, const Vec3& d) {
  if (n.is_leaf()) {
    const int axis = prism_axis_along(n.primitive, d);
    if (axis < 0) return std::nullopt;
    return leaf_span(n.primitive, axis, d);
  }
  std::optional<Span> out;
  for (const Node3D& c : n.children) {
    const std::optional<Span> s = extent(c, d);
    if (!s) return std::nullopt;
    if (!out)
      out = s;
    else if (n.kind == NodeKind::Union)
      out = Span{std::min(out->lo, s->lo), std::max(out->hi, s->hi)};
    else if (n.kind == NodeKind::Intersection)
      out = Span{std::max(out->lo, s->lo), std::min(out->hi, s->hi)};
  }
  return out;
}

// The subtree's extent along d when it is a linear sweep along d. Every leaf then spans the
// whole extent, so inside it each leaf is its section times the extent, and outside it the
// subtree is empty: the subtree is its leaves' sections, combined as it combines the leaves,
// swept over the extent.
std::optional<Span> linear_extent(const Node3D& n, const Vec3& d, double tolerance) {
  const std::optional<Span> e = extent(n, d);
  if (!e || e->hi - e->lo <= tolerance) return std::nullopt;
  for (const Primitive3D* p : leaves(n)) {
    const Span s = leaf_span(*p, prism_axis_along(*p, d), d);
    if (s.lo > e->lo + tolerance || s.hi < e->hi - tolerance) return std::nullopt;
  }
  return e;
}

// The frame a designer would place the profile in: along a model axis, no turn for z and the
// profile upright (its y up the model's z) for x and y; along any other direction, the first
// leaf's own axes (a tilted plate's profile is then its unturned drawing).
Quaternion linear_frame(const Primitive3D& first, int axis, const Vec3& d) {
  if (parallel(d, {0, 0, 1})) return {};
  if (parallel(d, {0, 1, 0})) return Quaternion::from_euler_deg(90, 0, 0);
  if (parallel(d, {1, 0, 0})) return Quaternion::from_euler_deg(90, 0, 90);
  const Mat3 m = first.rotation.matrix();
  Mat3 f;
  for (int r = 0; r < 3; ++r) {
    f[r][0] = m[r][(axis + 1) % 3];
    f[r][1] = m[r][(axis + 2) % 3];
    f[r][2] = m[r][axis];
  }
  return quaternion_from_matrix(f);
}

// An angle in (-period / 2, period / 2]: a rectangle turned by 180 degrees, or a regular
// n-gon by 360 / n, is the same shape.
double reduced(double degrees, double period) {
  double a = std::fmod(degrees, period);
  if (a > period / 2) a -= period;
  if (a <= -period / 2) a += period;
  return a;
}

SweepSection linear_section(const Primitive3D& p, const Mat3& frame, const Vec3& origin) {
  SweepSection s;
  s.leaf = &p;
  const Vec3 z = column(frame, 2);
  const int axis = prism_axis_along(p, z);
  const Vec3 at = in_frame(frame, sub(centre(p), origin));
  s.x = at[0];
  s.y = at[1];
  const Mat3 m = p.rotation.matrix();
  // A rectangle, rounded or not, is the same seen from either side and turned half round.
  const bool rectangle = p.kind == PrimitiveKind3D::Box || p.kind == PrimitiveKind3D::RoundedBox;
  if (rectangle) {
    // Its first side is the box's axis nearest the plane's x, so that an unturned box draws an
    // unturned square.
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const bool a_first = std::fabs(in_frame(frame, column(m, a))[0]) >=
                         std::fabs(in_frame(frame, column(m, b))[0]);
    s.across[0] = a_first ? a : b;
    s.across[1] = a_first ? b : a;
  }
  s.flipped = dot(column(m, axis), z) < 0;
  if (p.kind == PrimitiveKind3D::Cylinder && !p.is_polygonal()) return s;  // no angle to see
  const Vec3 u = in_frame(frame, column(m, s.across[0]));
  s.angle = std::atan2(u[1], u[0]) * kRadToDeg;
  if (rectangle) s.angle = reduced(s.angle, 180);
  if (p.is_polygonal()) s.angle = reduced(s.angle, 360.0 / p.sides);
  return s;
}

std::optional<Sweep> linear_sweep(const Node3D& n, double tolerance) {
  const std::vector<const Primitive3D*> ls = leaves(n);
  const Primitive3D& first = *ls.front();
  // Every leaf is a prism along the direction, so it is one of the first leaf's axes. A plate
  // is swept across its thickness: the smallest height wins, then the direction nearest the
  // model's z, then its y (a tree of boxes may be a sweep along all three).
  const Mat3 m = first.rotation.matrix();
  int best_axis = -1;
  Span best;
  auto nearer_z = [](const Vec3& a, const Vec3& b) {
    return std::fabs(a[2]) != std::fabs(b[2]) ? std::fabs(a[2]) > std::fabs(b[2])
                                              : std::fabs(a[1]) > std::fabs(b[1]);
  };
  for (int axis : prism_axes(first)) {
    const std::optional<Span> e = linear_extent(n, column(m, axis), tolerance);
    if (!e) continue;
    const double h = e->hi - e->lo, best_h = best.hi - best.lo;
    if (best_axis < 0 || h < best_h - tolerance ||
        (h <= best_h + tolerance && nearer_z(column(m, axis), column(m, best_axis))))
      best_axis = axis, best = *e;
  }
  if (best_axis < 0) return std::nullopt;
  const Vec3 d = column(m, best_axis);
  Sweep s;
  s.kind = SweepKind::Linear;
  s.root = &n;
  s.rotation = linear_frame(first, best_axis, d);
  const Mat3 frame = s.rotation.matrix();
  const Vec3 z = column(frame, 2);
  // The frame's z may point against d: the sweep starts at the extent's low end along z.
  const double start = dot(z, d) > 0 ? best.lo : -best.hi;
  s.origin = scale(z, start);
  s.height = best.hi - best.lo;
  for (const Primitive3D* p : ls) s.sections.push_back(linear_section(*p, frame, s.origin));
  return s;
}

// ---- revolutions ---------------------------------------------------------------------------

bool round_about_its_axis(const Primitive3D& p) {
  switch (p.kind) {
    case PrimitiveKind3D::Cylinder:
    case PrimitiveKind3D::Cone: return !p.is_polygonal();
    case PrimitiveKind3D::Torus:
    case PrimitiveKind3D::Sphere: return true;
    default: return false;
  }
}

std::optional<Sweep> revolution_sweep(const Node3D& n, double tolerance) {
  const std::vector<const Primitive3D*> ls = leaves(n);
  const Primitive3D* axis_leaf = nullptr;
  for (const Primitive3D* p : ls) {
    if (!round_about_its_axis(*p)) return std::nullopt;
    if (!axis_leaf && p->kind != PrimitiveKind3D::Sphere) axis_leaf = p;
  }
  // Spheres alone have no axis of their own.
  if (!axis_leaf) return std::nullopt;
  Vec3 d = column(axis_leaf->rotation.matrix(), 2);
  const Vec3 on_axis = centre(*axis_leaf);
  for (const Primitive3D* p : ls) {
    if (norm(reject(sub(centre(*p), on_axis), d)) > tolerance) return std::nullopt;
    if (p->kind != PrimitiveKind3D::Sphere && !parallel(column(p->rotation.matrix(), 2), d))
      return std::nullopt;
  }
  // The axis's largest component positive: up the model's z rather than down it.
  const auto largest = std::max_element(d.begin(), d.end(), [](double a, double b) {
    return std::fabs(a) < std::fabs(b);
  });
  if (*largest < 0) d = scale(d, -1);
  Sweep s;
  s.kind = SweepKind::Revolution;
  s.root = &n;
  // rotate([a, b, 0]) takes local z to d (as the .scad writer turns a cylinder).
  s.rotation = Quaternion::from_euler_deg(-std::asin(std::clamp(d[1], -1.0, 1.0)) * kRadToDeg,
                                          std::atan2(d[0], d[2]) * kRadToDeg, 0);
  s.origin = reject(on_axis, d);  // the point of the axis nearest the model's origin
  const Vec3 z = column(s.rotation.matrix(), 2);
  for (const Primitive3D* p : ls) {
    SweepSection section;
    section.leaf = p;
    section.y = dot(sub(centre(*p), s.origin), z);
    section.flipped = dot(column(p->rotation.matrix(), 2), z) < 0;
    s.sections.push_back(section);
  }
  return s;
}

// ---- the largest subtrees ------------------------------------------------------------------

struct Walk {
  double tolerance = 0;
  std::size_t node = 0, leaf = 0;  // pre-order indices of the next node and leaf
  std::vector<Sweep> found;
};

void find_in(const Node3D& n, Walk& walk) {
  if (!n.is_leaf() && n.primitive_count() >= 2 && well_formed(n)) {
    std::optional<Sweep> s = linear_sweep(n, walk.tolerance);
    if (!s) s = revolution_sweep(n, walk.tolerance);
    if (s) {
      s->node = walk.node;
      for (SweepSection& section : s->sections) section.leaf_index = walk.leaf++;
      walk.node += n.node_count();
      walk.found.push_back(std::move(*s));
      return;
    }
  }
  ++walk.node;
  if (n.is_leaf()) ++walk.leaf;
  for (const Node3D& c : n.children) find_in(c, walk);
}

}  // namespace

const SweepSection* Sweep::section_of(const Primitive3D* leaf) const {
  for (const SweepSection& s : sections)
    if (s.leaf == leaf) return &s;
  return nullptr;
}

std::vector<Sweep> find_sweeps(const Node3D& tree) {
  const std::vector<const Primitive3D*> ls = leaves(tree);
  if (ls.size() < 2) return {};
  Bounds3 b = ls.front()->bounds();
  for (const Primitive3D* p : ls) b = merged(b, p->bounds());
  const double size = std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  if (!std::isfinite(size) || !(size > 0)) return {};
  Walk walk;
  walk.tolerance = kLengthTolerance * size;
  find_in(tree, walk);
  return std::move(walk.found);
}

}  // namespace csgfit
