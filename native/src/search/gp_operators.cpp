#include "search/gp_operators.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace csgfit::gp {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

// The kinds that stand on the floor or open to the sky when vertical (their local z is an
// extent, not a radius).
bool is_extruded(PrimitiveKind3D k) {
  return k == PrimitiveKind3D::Box || k == PrimitiveKind3D::Cylinder ||
         k == PrimitiveKind3D::Cone || k == PrimitiveKind3D::TriangularPrism ||
         k == PrimitiveKind3D::RoundedBox;
}

void signed_leaves(Node3D& n, bool negative, std::vector<std::pair<Primitive3D*, bool>>& out) {
  if (n.is_leaf()) {
    out.push_back({&n.primitive, negative});
    return;
  }
  for (std::size_t i = 0; i < n.children.size(); ++i)
    signed_leaves(n.children[i], negative != (n.kind == NodeKind::Difference && i > 0), out);
}

std::vector<PrimitiveKind3D> allowed_kinds(const PrimitiveSet3D& set) {
  const PrimitiveSet3D analytic = analytic_kinds(set);
  std::vector<PrimitiveKind3D> out;
  for (int i = 0; i <= static_cast<int>(PrimitiveKind3D::RoundedBox); ++i)
    if (analytic.has(static_cast<PrimitiveKind3D>(i))) out.push_back(static_cast<PrimitiveKind3D>(i));
  if (out.empty()) out.push_back(PrimitiveKind3D::Box);
  return out;
}

// A terminal of `kind` with half extents he about centre c, turned by q.
Primitive3D make_terminal(PrimitiveKind3D kind, const Vec3& c, const Vec3& he, const Quaternion& q) {
  const double r = 0.5 * (he[0] + he[1]);
  switch (kind) {
    case PrimitiveKind3D::Sphere: return Primitive3D::sphere(c[0], c[1], c[2], (he[0] + he[1] + he[2]) / 3);
    case PrimitiveKind3D::Cylinder: return Primitive3D::cylinder(c[0], c[1], c[2], r, 2 * he[2], q);
    case PrimitiveKind3D::Cone: return Primitive3D::cone(c[0], c[1], c[2], r, r / 2, 2 * he[2], q);
    case PrimitiveKind3D::Ellipsoid: return Primitive3D::ellipsoid(c[0], c[1], c[2], he[0], he[1], he[2], q);
    case PrimitiveKind3D::Torus: return Primitive3D::torus(c[0], c[1], c[2], r, std::min(he[2], r), q);
    case PrimitiveKind3D::TriangularPrism:
      return Primitive3D::prism(c[0], c[1], c[2], 2 * he[0], 2 * he[1], 2 * he[2], 0, q);
    case PrimitiveKind3D::RoundedBox:
      return Primitive3D::rounded_box(c[0], c[1], c[2], 2 * he[0], 2 * he[1], 2 * he[2],
                                      std::min(he[0], he[1]) / 2, q);
    default: return Primitive3D::box(c[0], c[1], c[2], 2 * he[0], 2 * he[1], 2 * he[2], q);
  }
}

Vec3 half_extents(const Primitive3D& p) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Sphere:
    case PrimitiveKind3D::Ellipsoid: return d;
    case PrimitiveKind3D::Cylinder: return {d[0], d[0], d[2] / 2};
    case PrimitiveKind3D::Cone: return {std::max(d[0], d[1]), std::max(d[0], d[1]), d[2] / 2};
    case PrimitiveKind3D::Torus: return {d[0] + d[1], d[0] + d[1], d[1]};
    default: return {d[0] / 2, d[1] / 2, d[2] / 2};
  }
}

// The rotation taking local z to the unit vector n.
Quaternion z_to(const Vec3& n) {
  const double angle = std::acos(std::clamp(n[2], -1.0, 1.0)) * kRadToDeg;
  if (std::hypot(n[0], n[1]) < 1e-9) return n[2] > 0 ? Quaternion{} : Quaternion::from_axis_angle(1, 0, 0, 180);
  return Quaternion::from_axis_angle(-n[1], n[0], 0, angle);
}

struct Worst {
  std::size_t index = 0;
  double error = 0;  ///< > 0: the tree lacks material there; < 0: it has too much
};

Worst worst_point(const Node3D& tree, const Context& c, rnd::Rng& rng) {
  const PointTarget& t = *c.target;
  Worst w;
  for (int k = 0; k < 8; ++k) {
    const std::size_t i = c.subset->empty() ? rnd::pick(rng, t.points.size())
                                            : (*c.subset)[rnd::pick(rng, c.subset->size())];
    const Vec3& p = t.points[i];
    double e;
    if (t.scan == ScanKind::Top) {
      const double top = column_top(tree, p[0], p[1]);
      e = std::isfinite(top) ? p[2] - top : p[2] - t.floor;
    } else {
      e = signed_distance(tree, p[0], p[1], p[2]);
    }
    if (std::fabs(e) > std::fabs(w.error)) w = {i, e};
  }
  return w;
}

// A turn about the new terminal's axis: drawn parts are turned by multiples of 15 degrees far
// more often than by anything else.
double spin_degrees(rnd::Rng& rng) {
  if (rnd::uniform(rng, 0, 1) < 0.7) return 15.0 * (static_cast<double>(rnd::pick(rng, 13)) - 6);
  return rnd::uniform(rng, -90, 90);
}

Primitive3D new_terminal(const Context& c, const Worst& w, rnd::Rng& rng) {
  const PointTarget& t = *c.target;
  const std::vector<PrimitiveKind3D> kinds = allowed_kinds(c.primitives);
  const PrimitiveKind3D kind = kinds[rnd::pick(rng, kinds.size())];
  const double D = t.diagonal;
  Vec3 he{rnd::uniform(rng, 0.02, 0.25) * D, rnd::uniform(rng, 0.02, 0.25) * D, 0};
  if (rnd::uniform(rng, 0, 1) < 0.4) he[1] = he[0];
  const Vec3& p = t.points[w.index];
  const bool add = w.error > 0;
  if (t.scan == ScanKind::Top) {
    const Quaternion spin = Quaternion::from_axis_angle(0, 0, 1, spin_degrees(rng));
    if (kind == PrimitiveKind3D::Sphere || kind == PrimitiveKind3D::Ellipsoid) {
      he[2] = he[0];
      return make_terminal(kind, {p[0], p[1], add ? p[2] - he[0] : p[2] + he[0]}, he, spin);
    }
    const double lo = add ? t.floor : p[2], hi = add ? p[2] : t.top + 0.05 * D;
    he[2] = std::max(0.5 * (hi - lo), 1e-6 * D);
    return make_terminal(kind, {p[0], p[1], 0.5 * (lo + hi)}, he, spin);
  }
  he[2] = rnd::uniform(rng, 0.02, 0.25) * D;
  const Vec3& n = t.normals[w.index];
  const double s = add ? -he[2] : he[2];  // the centre behind the surface (add) or before it (cut)
  const Vec3 centre{p[0] + s * n[0], p[1] + s * n[1], p[2] + s * n[2]};
  const Quaternion q = Quaternion::from_axis_angle(n[0], n[1], n[2], spin_degrees(rng)) * z_to(n);
  return make_terminal(kind, centre, he, q);
}

std::vector<double> pack(const Primitive3D& p, double D) {
  std::vector<double> x{p.cx / D, p.cy / D, p.cz / D};
  int idx[3];
  const int n = free_dims(p.kind, idx);
  for (int i = 0; i < n; ++i) x.push_back(p.dims[idx[i]] / D);
  if (p.kind == PrimitiveKind3D::TriangularPrism) x.push_back(p.apex);
  if (has_free_corner(p.kind)) x.push_back(p.corner / D);
  return x;
}

void unpack(Primitive3D& p, const std::vector<double>& x, double D) {
  p.cx = x[0] * D, p.cy = x[1] * D, p.cz = x[2] * D;
  int idx[3];
  const int n = free_dims(p.kind, idx);
  for (int i = 0; i < n; ++i) p.dims[idx[i]] = std::fabs(x[3 + i]) * D;
  if (p.kind == PrimitiveKind3D::TriangularPrism) p.apex = x[3 + n];
  if (has_free_corner(p.kind)) p.corner = x[3 + n] * D;
  p.normalize();
}

}  // namespace

void mutate_terminals(GpIndividual& g, const Context& c, rnd::Rng& rng) {
  const std::vector<Primitive3D*> leaves = csgfit::leaves(g.tree);
  const double D = c.target->diagonal;
  const double rate = 1.0 / static_cast<double>(leaves.size());
  const std::size_t must = rnd::pick(rng, leaves.size());
  const es::StepRule rule = es::StepRule::standard(6, 1, 1e-6);
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    Primitive3D& p = *leaves[i];
    if (p.kind == PrimitiveKind3D::Nurbs) continue;  // fitted by least squares, not mutated
    if (i != must && rnd::uniform(rng, 0, 1) >= rate) continue;
    std::vector<double> x = pack(p, D), sigma{g.sigma[i]};
    es::mutate(x, sigma, rule, rng);
    g.sigma[i] = std::min(sigma[0], 0.5);
    unpack(p, x, D);
    // Turns are mutated less often: drawn parts are mostly square to their axes.
    if (p.kind != PrimitiveKind3D::Sphere && rnd::uniform(rng, 0, 1) < 0.2) {
      const Vec3 a{rnd::normal(rng, 0, 1), rnd::normal(rng, 0, 1), rnd::normal(rng, 0, 1)};
      const double turn = g.sigma[i] * rnd::normal(rng, 0, 1) * kRadToDeg;
      p.rotation = Quaternion::from_axis_angle(a[0], a[1], a[2], turn) * p.rotation;
      p.normalize();
    }
  }
}

bool mutate_relation(GpIndividual& g, rnd::Rng& rng) {
  std::vector<std::size_t> ops;
  for_each_node(g.tree, [&](const Node3D& n, std::size_t i) { if (!n.is_leaf()) ops.push_back(i); });
  if (ops.empty()) return false;
  Node3D* n = node_at(g.tree, ops[rnd::pick(rng, ops.size())]);
  static const NodeKind kinds[3] = {NodeKind::Union, NodeKind::Difference, NodeKind::Intersection};
  NodeKind next = n->kind;
  while (next == n->kind) next = kinds[rnd::pick(rng, 3)];
  n->kind = next;
  return true;
}

bool delete_subtree(GpIndividual& g, rnd::Rng& rng) {
  const std::size_t count = g.tree.node_count();
  if (count < 2) return false;
  return erase_subtree(g.tree, 1 + rnd::pick(rng, count - 1));
}

bool insert_terminal(GpIndividual& g, const Context& c, rnd::Rng& rng) {
  if (c.patch && rnd::uniform(rng, 0, 1) < 0.15) {
    graft(g.tree, NodeKind::Union, Node3D::leaf(*c.patch));
    return true;
  }
  const Worst w = worst_point(g.tree, c, rng);
  if (w.error == 0) return false;
  graft(g.tree, w.error > 0 ? NodeKind::Union : NodeKind::Difference, Node3D::leaf(new_terminal(c, w, rng)));
  return true;
}

Node3D seed_terminal(const Context& c, rnd::Rng& rng) {
  const std::size_t i = c.subset->empty() ? rnd::pick(rng, c.target->points.size())
                                          : (*c.subset)[rnd::pick(rng, c.subset->size())];
  return Node3D::leaf(new_terminal(c, Worst{i, 1.0}, rng));
}

bool replace_terminal(GpIndividual& g, const Context& c, rnd::Rng& rng) {
  const std::vector<Primitive3D*> leaves = csgfit::leaves(g.tree);
  Primitive3D& p = *leaves[rnd::pick(rng, leaves.size())];
  if (p.kind == PrimitiveKind3D::Nurbs) return false;
  const std::vector<PrimitiveKind3D> kinds = allowed_kinds(c.primitives);
  const PrimitiveKind3D kind = kinds[rnd::pick(rng, kinds.size())];
  if (kind == p.kind) return false;
  p = make_terminal(kind, {p.cx, p.cy, p.cz}, half_extents(p), p.rotation);
  return true;
}

GpIndividual exchange_subtrees(const GpIndividual& a, const GpIndividual& b, rnd::Rng& rng) {
  GpIndividual child = a;
  Node3D* at = node_at(child.tree, rnd::pick(rng, child.tree.node_count()));
  const Node3D* from = node_at(const_cast<Node3D&>(b.tree), rnd::pick(rng, b.tree.node_count()));
  *at = *from;
  double mean = 0;
  for (double s : a.sigma) mean += s;
  for (double s : b.sigma) mean += s;
  mean /= static_cast<double>(std::max<std::size_t>(1, a.sigma.size() + b.sigma.size()));
  child.sigma.assign(csgfit::leaves(child.tree).size(), mean);
  return child;
}

// The local axis of p that stands upright (a box may stand on any face; the round kinds and
// the prism only along their local z), or -1.
int upright_axis(const Primitive3D& p) {
  const Mat3 m = p.rotation.matrix();
  const int last = p.kind == PrimitiveKind3D::Box ? 2 : 0;
  for (int a = 0; a <= last; ++a) {
    const int axis = p.kind == PrimitiveKind3D::Box ? a : 2;
    if (std::fabs(m[2][axis]) > 0.9999) return axis;
  }
  return -1;
}

void ground(Node3D& tree, const PointTarget& t) {
  if (t.scan != ScanKind::Top) return;
  const double sky = t.top + 0.05 * t.diagonal;
  std::vector<std::pair<Primitive3D*, bool>> leaves;
  signed_leaves(tree, false, leaves);
  for (auto& [p, negative] : leaves) {
    if (!is_extruded(p->kind)) continue;
    const int a = upright_axis(*p);
    if (a < 0) continue;
    double lo = p->cz - p->dims[a] / 2, hi = p->cz + p->dims[a] / 2;
    if (negative) hi = std::max(hi, sky);
    else lo = t.floor;
    if (!(hi > lo)) continue;
    p->dims[a] = hi - lo;
    p->cz = 0.5 * (hi + lo);
    p->normalize();
  }
}

bool tidy(GpIndividual& g, const Context& c) {
  if (!simplify(g.tree) || g.tree.primitive_count() == 0) return false;
  ground(g.tree, *c.target);
  const std::size_t n = csgfit::leaves(g.tree).size();
  if (g.sigma.size() != n) g.sigma.resize(n, c.first_sigma);
  return true;
}

}  // namespace csgfit::gp
