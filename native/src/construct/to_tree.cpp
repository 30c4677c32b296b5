#include "to_tree.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "model/linalg.h"

namespace csgfit::construct {

namespace {

using namespace linalg;

constexpr double kHuge = 1e300;

// A box's worth of planes: intervals along up to three perpendicular directions. The first
// frame of a product is the model axes; planes along other directions make frames of their own
// ("planes that bound one box become that box", however the box is turned).
struct Frame {
  std::array<Vec3, 3> axis{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  std::array<bool, 3> defined{true, true, true};
  std::array<double, 3> lo{-kHuge, -kHuge, -kHuge}, hi{kHuge, kHuge, kHuge};
  bool constrained() const {
    for (int k = 0; k < 3; ++k)
      if (lo[k] > -kHuge || hi[k] < kHuge) return true;
    return false;
  }
};

// Directions agree to the file's rounding: a float STL states a turned face's normal to about
// 1e-6 (a design never turns two faces by 1e-5 radians on purpose).
constexpr double kSameDirection = 1e-5;

bool parallel(const Vec3& a, const Vec3& b) { return norm(cross(a, b)) < kSameDirection; }

// The halfspace n . x <= d of a plane term, on its side.
void halfspace(const Literal& l, bool inside, Vec3& n, double& d) {
  n = inside ? l.normal : scale(l.normal, -1);
  d = inside ? l.offset : -l.offset;
}

void tighten(Frame& f, int k, const Vec3& n, double d) {
  if (dot(f.axis[k], n) > 0) f.hi[k] = std::min(f.hi[k], d);
  else f.lo[k] = std::max(f.lo[k], -d);
}

// Adds the halfspace n . x <= d to the frame along n, or to one it completes, or to a new one.
void add_plane(std::vector<Frame>& frames, const Vec3& n, double d) {
  for (Frame& f : frames)
    for (int k = 0; k < 3; ++k)
      if (f.defined[k] && parallel(f.axis[k], n)) return tighten(f, k, n, d);
  for (Frame& f : frames) {
    int free_slot = -1;
    bool across = true;
    for (int k = 0; k < 3; ++k) {
      if (!f.defined[k]) free_slot = free_slot < 0 ? k : free_slot;
      else across = across && std::abs(dot(f.axis[k], n)) < kSameDirection;
    }
    if (free_slot < 0 || !across) continue;
    f.axis[free_slot] = n, f.defined[free_slot] = true;
    return tighten(f, free_slot, n, d);
  }
  Frame f;
  f.defined = {true, false, false};
  f.axis[0] = n;
  tighten(f, 0, n, d);
  frames.push_back(f);
}

// The reach of a box along a unit direction.
void reach(const Bounds3& b, const Vec3& d, double& lo, double& hi) {
  lo = kHuge, hi = -kHuge;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{corner & 1 ? b.hi[0] : b.lo[0], corner & 2 ? b.hi[1] : b.lo[1], corner & 4 ? b.hi[2] : b.lo[2]};
    lo = std::min(lo, dot(p, d)), hi = std::max(hi, dot(p, d));
  }
}

// The frame's axes completed to a right-handed triple, its intervals closed by `bounds`.
Frame closed(Frame f, const Bounds3& bounds) {
  if (!f.defined[1] || !f.defined[2]) {
    const int first = f.defined[1] ? 1 : (f.defined[2] ? 2 : 0);
    const Mat3 m = frame_along(f.axis[first == 0 ? 0 : first], {1, 0, 0}).matrix();
    if (f.defined[0] && (f.defined[1] || f.defined[2])) {
      const int known = f.defined[1] ? 1 : 2, missing = 3 - known;
      f.axis[missing] = cross(f.axis[0], f.axis[known]);
    } else {
      f.axis[1] = column(m, 0), f.axis[2] = column(m, 1);
    }
    f.defined = {true, true, true};
  }
  if (dot(cross(f.axis[0], f.axis[1]), f.axis[2]) < 0) {
    f.axis[2] = scale(f.axis[2], -1);
    std::swap(f.lo[2], f.hi[2]);
    f.lo[2] = -f.lo[2], f.hi[2] = -f.hi[2];
  }
  for (int k = 0; k < 3; ++k) {
    double lo, hi;
    reach(bounds, f.axis[k], lo, hi);
    f.lo[k] = std::max(f.lo[k], lo), f.hi[k] = std::min(f.hi[k], hi);
  }
  return f;
}

Node3D box_node(const Frame& f) {
  Vec3 c{0, 0, 0};
  for (int k = 0; k < 3; ++k) c = add(c, scale(f.axis[k], 0.5 * (f.lo[k] + f.hi[k])));
  Mat3 m;
  for (int r = 0; r < 3; ++r) m[r] = {f.axis[0][r], f.axis[1][r], f.axis[2][r]};
  const bool model = f.axis[0][0] == 1 && f.axis[1][1] == 1 && f.axis[2][2] == 1;
  return Node3D::leaf(Primitive3D::box(c[0], c[1], c[2], f.hi[0] - f.lo[0], f.hi[1] - f.lo[1], f.hi[2] - f.lo[2],
                                       model ? Quaternion{} : quaternion_from_matrix(m)));
}

// A cylinder or cone literal cut to [t0, t1] along its own axis (measured from its centre).
Primitive3D cut_along_axis(Primitive3D p, double t0, double t1) {
  const Vec3 axis = column(p.rotation.matrix(), 2);
  const double h = p.dims[2];
  t0 = std::max(t0, -h / 2), t1 = std::min(t1, h / 2);
  if (p.kind == PrimitiveKind3D::Cone) {
    const double slope = (p.dims[1] - p.dims[0]) / h;
    const double r0 = p.dims[0] + slope * (t0 + h / 2), r1 = p.dims[0] + slope * (t1 + h / 2);
    p.dims[0] = r0, p.dims[1] = r1;
  }
  const double mid = 0.5 * (t0 + t1);
  p.cx += axis[0] * mid, p.cy += axis[1] * mid, p.cz += axis[2] * mid;
  p.dims[2] = t1 - t0;
  p.normalize();
  return p;
}

// Primitives along their local z whose ends the planes across it may be: a cylinder's caps, a
// rounded box's top and bottom.
bool has_axis(const Primitive3D& p) {
  return p.kind == PrimitiveKind3D::Cylinder || p.kind == PrimitiveKind3D::Cone || p.kind == PrimitiveKind3D::RoundedBox;
}

// Cuts an axial primitive to `bounds` and to the frames' intervals along its axis, which become
// its own ends (a cylinder takes the caps across it).
void fit_axial(Primitive3D& p, std::vector<Frame>& frames, const Bounds3& bounds) {
  const Vec3 axis = column(p.rotation.matrix(), 2);
  const double at = dot(Vec3{p.cx, p.cy, p.cz}, axis);
  double t0, t1;
  reach(bounds, axis, t0, t1);
  t0 -= at, t1 -= at;
  for (Frame& f : frames)
    for (int k = 0; k < 3; ++k) {
      if (!f.defined[k] || !parallel(f.axis[k], axis)) continue;
      const double s = dot(f.axis[k], axis) > 0 ? 1 : -1;
      const double lo = s > 0 ? f.lo[k] : -f.hi[k], hi = s > 0 ? f.hi[k] : -f.lo[k];
      t0 = std::max(t0, lo - at), t1 = std::min(t1, hi - at);
      f.lo[k] = -kHuge, f.hi[k] = kHuge;
    }
  p = cut_along_axis(p, t0, t1);
}

// Whether the (closed) frame's box cuts the primitive: the primitive's bounds reach past it.
bool box_cuts(const Frame& f, const Primitive3D& p) {
  const Bounds3 b = p.bounds();
  for (int k = 0; k < 3; ++k) {
    double lo, hi;
    reach(b, f.axis[k], lo, hi);
    if (lo < f.lo[k] - 1e-9 || hi > f.hi[k] + 1e-9) return true;
  }
  return false;
}

// The product's solid: its curved sides cut to its planes, less its curved holes. A positive
// lies in `bounds` (its box cuts what reaches past them); a hole may reach past them.
Node3D solid_of(const Product& product, const std::vector<Literal>& literals, const Bounds3& bounds,
                bool inside_bounds) {
  std::vector<Frame> frames(1);  // the model axes first
  std::vector<Primitive3D> curved, cut_out;
  for (const Term& t : product) {
    const Literal& l = literals[static_cast<std::size_t>(t.literal)];
    if (!l.plane) {
      (t.inside ? curved : cut_out).push_back(l.solid);
      continue;
    }
    Vec3 n;
    double d;
    halfspace(l, t.inside, n, d);
    add_plane(frames, n, d);
  }
  std::vector<Node3D> parts;
  std::vector<Bounds3> reaches;  // each part's bounds: the solid lies in all of them
  for (Primitive3D& p : curved) {
    if (has_axis(p)) fit_axial(p, frames, bounds);
    parts.push_back(Node3D::leaf(p));
    reaches.push_back(p.bounds());
  }
  // A turned frame is a box where it still cuts a round primitive (or where there is none).
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const Frame f = closed(frames[i], bounds);
    if (!curved.empty() && std::none_of(curved.begin(), curved.end(), [&](const Primitive3D& p) { return box_cuts(f, p); }))
      continue;
    parts.push_back(box_node(f));
    reaches.push_back(parts.back().primitive.bounds());
  }
  // The model frame, closed by the bounds a positive lies in, is a box where something would
  // reach past it: a round primitive, a turned box, or nothing else at all.
  Frame model = closed(frames[0], bounds);
  for (const Bounds3& b : reaches)
    for (int a = 0; a < 3; ++a) model.lo[a] = std::max(model.lo[a], b.lo[a]), model.hi[a] = std::min(model.hi[a], b.hi[a]);
  const bool past = std::any_of(reaches.begin(), reaches.end(), [&](const Bounds3& b) {
    for (int a = 0; a < 3; ++a)
      if (b.lo[a] < model.lo[a] - 1e-9 || b.hi[a] > model.hi[a] + 1e-9) return true;
    return false;
  });
  if ((parts.empty() || past) && (inside_bounds || frames[0].constrained())) parts.push_back(box_node(model));
  Node3D solid = parts.size() == 1 ? parts.front() : Node3D::op(NodeKind::Intersection, parts);
  if (cut_out.empty()) return solid;
  std::vector<Node3D> kids{solid};
  for (Primitive3D p : cut_out) {
    if (has_axis(p)) {
      std::vector<Frame> none;
      fit_axial(p, none, bounds);
    }
    kids.push_back(Node3D::leaf(p));
  }
  return Node3D::op(NodeKind::Difference, kids);
}

Bounds3 envelope_bounds(const Product& envelope, const std::vector<Literal>& literals, const Bounds3& domain) {
  Bounds3 b = domain;
  for (const Term& t : envelope) {
    const Literal& l = literals[static_cast<std::size_t>(t.literal)];
    if (!l.plane) continue;
    Vec3 n;
    double d;
    halfspace(l, t.inside, n, d);
    const int a = model_axis(n);
    if (a < 0) continue;
    if (n[a] > 0) b.hi[a] = std::min(b.hi[a], d);
    else b.lo[a] = std::max(b.lo[a], -d);
  }
  return b;
}

}  // namespace

std::optional<Node3D> tree_of(const Cover& cover, const std::vector<Literal>& literals, const Bounds3& domain) {
  const Bounds3 inner = envelope_bounds(cover.envelope, literals, domain);
  // The envelope's other sides: a solid the part lies outside of is a hole through it all; a
  // slanted face or a ball the part is cut from cuts what the positives, cut to its box, hold.
  Product cuts;
  std::vector<Product> holes_of_all = cover.holes;
  for (const Term& t : cover.envelope) {
    const Literal& l = literals[static_cast<std::size_t>(t.literal)];
    if (!l.plane && !t.inside) holes_of_all.push_back({{t.literal, true}});
    else if (!l.plane || model_axis(l.normal) < 0) cuts.push_back(t);
  }
  std::vector<Node3D> positives, holes;
  // With cuts, the whole box (an empty product) is the cuts' solid alone.
  for (const Product& p : cover.positives)
    if (!p.empty() || cuts.empty()) positives.push_back(solid_of(p, literals, inner, true));
  for (const Product& h : holes_of_all) holes.push_back(solid_of(h, literals, domain, false));
  const bool whole = positives.size() < cover.positives.size();
  if (cover.positives.empty()) return std::nullopt;
  Node3D tree;
  if (whole) {
    tree = solid_of(cuts, literals, inner, true);
  } else {
    tree = positives.size() == 1 ? positives.front() : Node3D::op(NodeKind::Union, positives);
    if (!cuts.empty()) tree = Node3D::op(NodeKind::Intersection, {solid_of(cuts, literals, inner, true), tree});
  }
  if (!holes.empty()) {
    holes.insert(holes.begin(), tree);
    tree = Node3D::op(NodeKind::Difference, holes);
  }
  simplify(tree);
  return tree;
}

}  // namespace csgfit::construct
