// The 3D search's perturbations: ADD matches a primitive to the residual, INT trims the tree
// with a primitive matched to the whole target, CUT, MOD and REP as in seed 000.
#include "search/operators3d.h"

#include <algorithm>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/features3d.h"
#include "csgfit/optimise/prune.h"
#include "csgfit/seed/decompose3d.h"
#include "search/operators.h"

namespace csgfit {

using rnd::pick;
using rnd::uniform;
using search_ops::Operator;

namespace {

// Half-extents of a primitive in its local frame: what MOD and REP keep when changing its kind.
Vec3 half_extents(const Primitive3D& p) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::Nurbs:
    case PrimitiveKind3D::RoundedBox:
    case PrimitiveKind3D::TriangularPrism: return {d[0] / 2, d[1] / 2, d[2] / 2};
    case PrimitiveKind3D::Cylinder: return {d[0], d[0], d[2] / 2};
    case PrimitiveKind3D::Cone: {
      const double r = std::max(d[0], d[1]);
      return {r, r, d[2] / 2};
    }
    case PrimitiveKind3D::Torus: return {d[0] + d[1], d[0] + d[1], d[1]};
    case PrimitiveKind3D::Sphere:
    case PrimitiveKind3D::Ellipsoid: return d;
  }
  return d;
}

Primitive3D with_kind(const Primitive3D& p, PrimitiveKind3D kind, const Vec3& he) {
  const double cx = p.cx, cy = p.cy, cz = p.cz;
  const Quaternion& q = p.rotation;
  Primitive3D out;
  switch (kind) {
    // The voxel search has no patch to fit: it never turns a leaf into a NURBS terminal.
    case PrimitiveKind3D::Nurbs:
    case PrimitiveKind3D::Box: out = Primitive3D::box(cx, cy, cz, 2 * he[0], 2 * he[1], 2 * he[2], q); break;
    case PrimitiveKind3D::Sphere: out = Primitive3D::sphere(cx, cy, cz, (he[0] + he[1] + he[2]) / 3); break;
    case PrimitiveKind3D::Cylinder:
      out = Primitive3D::cylinder(cx, cy, cz, (he[0] + he[1]) / 2, 2 * he[2], q);
      break;
    case PrimitiveKind3D::Cone:
      out = Primitive3D::cone(cx, cy, cz, (he[0] + he[1]) / 2, (he[0] + he[1]) / 4, 2 * he[2], q);
      break;
    case PrimitiveKind3D::Ellipsoid: out = Primitive3D::ellipsoid(cx, cy, cz, he[0], he[1], he[2], q); break;
    case PrimitiveKind3D::Torus: {
      const double r = std::max(he[2], 0.25 * (he[0] + he[1]) / 2);
      out = Primitive3D::torus(cx, cy, cz, std::max(r, (he[0] + he[1]) / 2 - r), r, q);
      break;
    }
    case PrimitiveKind3D::TriangularPrism:
      out = Primitive3D::prism(cx, cy, cz, 2 * he[0], 2 * he[1], 2 * he[2], 0, q);
      break;
    case PrimitiveKind3D::RoundedBox:
      // Halfway between the box and the stadium; the local optimiser moves it from there.
      out = Primitive3D::rounded_box(cx, cy, cz, 2 * he[0], 2 * he[1], 2 * he[2],
                                     std::min(he[0], he[1]) / 2, q);
      break;
  }
  out.normalize();
  return out;
}

// ADD at the residual: the thick part (one erosion removes the one-voxel skins a slightly
// misplaced primitive leaves) of what the tree gets wrong, matched by seed 003's matcher.

}  // namespace

Candidate3D Operators3D::evaluate(Node3D tree, const std::vector<Primitive3D>& fresh,
                                  bool polish_all) {
  Candidate c;
  if (!simplify(tree)) return c;
  TreeEvaluator3D ev(*pb_.target, tree);
  search_ops::optimise_perturbed(ev, fresh, pb_.new_leaf_opt, polish_all ? &pb_.all_leaf_opt : nullptr);
  evaluations += ev.evaluations();
  c.mismatch = ev.mismatch();
  c.primitives = tree.primitive_count();
  c.score = score(c.mismatch, c.primitives, pb_.k);
  c.result = ev.result();
  c.tree = std::move(tree);
  return c;
}

void Operators3D::accept(Candidate& c) {
  if (prune(c.tree, *pb_.target, pb_.k) == 0) return;
  c = scored(pb_, std::move(c.tree), evaluations);
}

Candidate3D Operators3D::scored(const Problem3D& pb, Node3D tree, std::size_t& evaluations) {
  Candidate c;
  if (tree.primitive_count() == 0) return c;
  TreeEvaluator3D ev(*pb.target, tree);
  evaluations += ev.evaluations() + tree.primitive_count();
  c.mismatch = ev.mismatch();
  c.primitives = tree.primitive_count();
  c.score = score(c.mismatch, c.primitives, pb.k);
  c.result = ev.result();
  c.tree = std::move(tree);
  return c;
}

std::optional<Primitive3D> Operators3D::residual_match(const VoxelGrid& raster, bool as_union) {
  VoxelGrid residual = as_union ? *pb_.target : raster;
  residual.subtract(as_union ? raster : *pb_.target);
  std::vector<Region3D> comps = connected_regions3d(erode6(residual), 6);
  if (comps.empty()) return std::nullopt;
  std::stable_sort(comps.begin(), comps.end(),
                   [](const Region3D& a, const Region3D& b) { return a.volume > b.volume; });
  const std::size_t n = std::min<std::size_t>(comps.size(), 6);
  const Region3D& core = comps[std::min(pick(rng_, n), pick(rng_, n))];
  // Grow the core back into the residual around it.
  const int lo[3] = {core.lo[0] - 1, core.lo[1] - 1, core.lo[2] - 1};
  const int hi[3] = {core.hi[0] + 1, core.hi[1] + 1, core.hi[2] + 1};
  std::vector<Region3D> around = connected_regions3d(crop(residual, lo, hi, 0), 6);
  if (around.empty()) return std::nullopt;
  const Region3D* region = &around.front();
  for (const Region3D& r : around)
    if (r.volume > region->volume) region = &r;
  auto match = match_region3d(region->mask, pb_.primitives);
  if (!match) return std::nullopt;
  return match->primitive;
}

bool Operators3D::add(Node3D& tree, const VoxelGrid& raster, std::vector<Primitive3D>& fresh) {
  if (!pb_.proposals.empty() && rng_() % 2 == 0)
    return search_ops::add_proposal(tree, pb_.proposals, rng_, fresh);
  const bool as_union = rng_() & 1;
  const std::optional<Primitive3D> match = residual_match(raster, as_union);
  if (!match) return false;
  fresh.push_back(*match);
  const std::size_t nodes = tree.node_count();
  Node3D* at = (rng_() % 2 == 0) ? &tree : node_at(tree, pick(rng_, nodes));
  graft(*at, as_union ? NodeKind::Union : NodeKind::Difference, Node3D::leaf(*match));
  return true;
}

Primitive3D Operators3D::changed_kind(const Primitive3D& p, bool new_orientation) {
  PrimitiveKind3D kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
  if (!new_orientation)
    while (kind == p.kind) kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
  Vec3 he = half_extents(p);
  Primitive3D np = p;
  if (new_orientation) {
    for (double& h : he) h *= uniform(rng_, 0.6, 1.4);
    np.rotation = Quaternion::from_euler_deg(uniform(rng_, -180, 180), uniform(rng_, -90, 90),
                                             uniform(rng_, -180, 180));
  }
  return with_kind(np, kind, he);
}

Primitive3D Operators3D::rekinded(const Primitive3D& p, PrimitiveKind3D kind) {
  return with_kind(p, kind, half_extents(p));
}

// MOD (same place and size, another kind) or REP (another kind, a new orientation).
bool Operators3D::change_kind(Node3D& tree, std::vector<Primitive3D>& fresh, bool new_orientation) {
  if (pb_.kinds.size() < 2 && !new_orientation) return false;
  std::vector<Primitive3D*> ls = leaves(tree);
  Primitive3D* p = ls[pick(rng_, ls.size())];
  *p = changed_kind(*p, new_orientation);
  fresh.push_back(*p);
  return true;
}

std::optional<Primitive3D> Operators3D::trimming_hull() {
  if (pb_.hulls.empty()) return std::nullopt;
  Primitive3D hull = pb_.hulls[pick(rng_, pb_.hulls.size())];
  const double grow = uniform(rng_, 1.0, 1.3);
  for (double& d : hull.dims) d *= grow;
  hull.normalize();
  return hull;
}

// INT: the tree (or a subtree) intersected with a round primitive matched to the whole
// target, a little larger than the match so that it trims rather than eats.
bool Operators3D::intersect(Node3D& tree, std::vector<Primitive3D>& fresh) {
  const std::optional<Primitive3D> hull = trimming_hull();
  if (!hull) return false;
  fresh.push_back(*hull);
  const std::size_t nodes = tree.node_count();
  Node3D* at = (rng_() % 4 != 0) ? &tree : node_at(tree, pick(rng_, nodes));
  graft(*at, NodeKind::Intersection, Node3D::leaf(*hull));
  return true;
}

Candidate3D Operators3D::perturb(const Candidate& parent) {
  Node3D tree = parent.tree;
  std::vector<Primitive3D> fresh;
  bool done = false;
  switch (search_ops::draw_operator(rng_, pb_.params.odds)) {
    case Operator::Add: done = add(tree, parent.result, fresh); break;
    case Operator::Intersect: done = intersect(tree, fresh); break;
    case Operator::Cut: done = search_ops::cut(tree, rng_); break;
    case Operator::Mod: done = change_kind(tree, fresh, false); break;
    case Operator::Rep: break;
  }
  // REP, also the fallback when another operator had nothing to act on.
  if (!done) change_kind(tree, fresh, true);
  ++trees;
  // A cut changes no primitive: its neighbours get a short polish instead.
  return evaluate(std::move(tree), fresh, fresh.empty());
}

}  // namespace csgfit
