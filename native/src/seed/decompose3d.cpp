#include "csgfit/seed/decompose3d.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/refine/local_opt.h"
#include "seed/triangle_frame.h"
#include "model/linalg.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;

using linalg::column;

// A right-handed frame whose local x, y, z are the given unit vectors.
Quaternion frame(const Vec3& x, const Vec3& y, const Vec3& z) {
  Mat3 m;
  for (int r = 0; r < 3; ++r) m[r][0] = x[r], m[r][1] = y[r], m[r][2] = z[r];
  return quaternion_from_matrix(m);
}

Vec3 axpy(const Vec3& p, double a, const Vec3& d) {
  return {p[0] + a * d[0], p[1] + a * d[1], p[2] + a * d[2]};
}

Vec3 neg(const Vec3& v) { return {-v[0], -v[1], -v[2]}; }

// Moments of a frustum with unit height and bottom radius 1, top radius t, bottom at z = 0:
// centroid height, variance along the axis and variance across it (a disc of radius r has
// r^2/4 about each diameter). Midpoint rule: accurate to ~1e-5, far below a voxel.
struct FrustumMoments {
  double zbar, vz, vp;
};
FrustumMoments frustum_moments(double t) {
  const int n = 400;
  double v = 0, m1 = 0, m2 = 0, p = 0;
  for (int i = 0; i < n; ++i) {
    const double z = (i + 0.5) / n, r = 1 + (t - 1) * z, a = r * r;
    v += a, m1 += z * a, m2 += z * z * a, p += a * r * r / 4;
  }
  const double zbar = m1 / v;
  return {zbar, m2 / v - zbar * zbar, p / v};
}

// Simpler kinds first: the order breaks ties between equal mismatches.
int simplicity(PrimitiveKind3D k) {
  switch (k) {
    case PrimitiveKind3D::Box: return 0;
    case PrimitiveKind3D::Sphere: return 1;
    case PrimitiveKind3D::Cylinder: return 2;
    case PrimitiveKind3D::Ellipsoid: return 3;
    case PrimitiveKind3D::Cone: return 4;
    case PrimitiveKind3D::TriangularPrism: return 5;
    case PrimitiveKind3D::Torus: return 6;
    case PrimitiveKind3D::Nurbs: return 7;
    case PrimitiveKind3D::RoundedBox: return 8;  // never matched: moments miss its corner
  }
  return 9;
}

}  // namespace

namespace {

struct Candidate {
  Primitive3D p;
  std::size_t mismatch;
};

// Frusta with these top / bottom radius ratios are tried (0: a full cone).
constexpr double kConeRatios[3] = {0.0, 1.0 / 3, 2.0 / 3};

// The moment-matched candidates of one region, the best of each kind by voxel mismatch.
class MomentMatcher {
 public:
  MomentMatcher(const VoxelGrid& region, const Moments3D& m, PrimitiveSet3D allowed)
      : region_(region),
        scratch_(region.nx(), region.ny(), region.nz(), region.origin_x(), region.origin_y(),
                 region.origin_z(), region.voxel_size()),
        allowed_(allowed),
        c_(m.centroid),
        best_of_(7, Candidate{Primitive3D{}, static_cast<std::size_t>(-1)}) {
    const double s = region.voxel_size();
    const double min_var = s * s / 12;
    for (int i = 0; i < 3; ++i) lam_[i] = std::max(m.variances[i], min_var);
    for (int i = 0; i < 3; ++i) e_[i] = column(m.axes, i);
  }

  const Vec3& variances() const { return lam_; }

  // Box, ellipsoid and sphere on the principal axes.
  void add_principal() {
    const Vec3& c = c_;
    const Vec3& lam = lam_;
    const Quaternion principal = frame(e_[0], e_[1], e_[2]);
    add(Primitive3D::box(c[0], c[1], c[2], std::sqrt(12 * lam[0]), std::sqrt(12 * lam[1]),
                         std::sqrt(12 * lam[2]), principal));
    add(Primitive3D::ellipsoid(c[0], c[1], c[2], std::sqrt(5 * lam[0]), std::sqrt(5 * lam[1]),
                               std::sqrt(5 * lam[2]), principal));
    add(Primitive3D::sphere(c[0], c[1], c[2], std::sqrt(5 * (lam[0] + lam[1] + lam[2]) / 3)));
  }

  // Cylinder, cones and prisms with their local z along principal axis ax; the other two axes
  // (cyclic, so the frame stays right-handed) span the cross-section.
  void add_along(int ax, const FrustumMoments fm[3]) {
    const Vec3& c = c_;
    const Vec3& lam = lam_;
    const Vec3& u = e_[(ax + 1) % 3];
    const Vec3& v = e_[(ax + 2) % 3];
    const Vec3& w = e_[ax];
    const double lp = 0.5 * (lam[(ax + 1) % 3] + lam[(ax + 2) % 3]);
    const Quaternion q = frame(u, v, w);
    add(Primitive3D::cylinder(c[0], c[1], c[2], 2 * std::sqrt(lp), std::sqrt(12 * lam[ax]), q));
    if (allowed_.has(PrimitiveKind3D::Cone)) {
      for (int t = 0; t < 3; ++t) {
        const double h = std::sqrt(lam[ax] / fm[t].vz), r1 = std::sqrt(lp / fm[t].vp);
        for (int dir = 0; dir < 2; ++dir) {
          // dir 1: the wide end the other way round.
          const Vec3 zz = dir == 0 ? w : neg(w), xx = dir == 0 ? u : neg(u);
          const Vec3 centre = axpy(c, (0.5 - fm[t].zbar) * h, zz);
          add(Primitive3D::cone(centre[0], centre[1], centre[2], r1, kConeRatios[t] * r1, h,
                                frame(xx, v, zz)));
        }
      }
    }
    if (allowed_.has(PrimitiveKind3D::TriangularPrism)) add_prisms(ax, u, v, w);
  }

  std::vector<Candidate> candidates() const {
    std::vector<Candidate> out;
    for (const Candidate& cd : best_of_)
      if (cd.mismatch != static_cast<std::size_t>(-1)) out.push_back(cd);
    return out;
  }

 private:
  void add(Primitive3D p) {
    if (!allowed_.has(p.kind)) return;
    p.normalize();
    rasterize(p, scratch_);
    const std::size_t mm = count_xor(scratch_, region_);
    Candidate& b = best_of_[static_cast<std::size_t>(p.kind)];
    if (mm < b.mismatch) b = {p, mm};
  }

  // Every triangle is an affine image of the equilateral one (covariance I/8 at circumradius
  // 1); the triangles with this cross-section's covariance form a one-parameter family in phi
  // (as in the 2D matcher).
  void add_prisms(int ax, const Vec3& u, const Vec3& v, const Vec3& w) {
    const Vec3& c = c_;
    const Vec3& lam = lam_;
    const double s1 = std::sqrt(8 * lam[(ax + 1) % 3]), s2 = std::sqrt(8 * lam[(ax + 2) % 3]);
    const double depth = std::sqrt(12 * lam[ax]);
    for (int step = 0; step < 12; ++step) {
      const double phi = step * 10.0 * kPi / 180;
      double tv[3][2];
      for (int i = 0; i < 3; ++i) {
        const double a = phi + kPi / 2 + i * 2 * kPi / 3;
        tv[i][0] = s1 * std::cos(a);
        tv[i][1] = s2 * std::sin(a);
      }
      const TriangleFrame t = triangle_frame(tv);
      const double ca = std::cos(t.angle), sa = std::sin(t.angle);
      const Vec3 xx = {ca * u[0] + sa * v[0], ca * u[1] + sa * v[1], ca * u[2] + sa * v[2]};
      const Vec3 yy = {-sa * u[0] + ca * v[0], -sa * u[1] + ca * v[1], -sa * u[2] + ca * v[2]};
      const Vec3 centre = axpy(axpy(c, t.cx, u), t.cy, v);
      add(Primitive3D::prism(centre[0], centre[1], centre[2], t.w, t.h, depth, t.apex,
                             frame(xx, yy, w)));
    }
  }

  const VoxelGrid& region_;
  VoxelGrid scratch_;
  PrimitiveSet3D allowed_;
  Vec3 lam_;
  Vec3 e_[3];
  Vec3 c_;
  std::vector<Candidate> best_of_;
};

bool better(const Candidate& a, const Candidate& b) {
  if (a.mismatch != b.mismatch) return a.mismatch < b.mismatch;
  return simplicity(a.p.kind) < simplicity(b.p.kind);
}

// Moments of a digitised shape are only approximately the continuous one's: the most
// promising kinds are refined against the region itself, and the winner is picked.
Candidate refine_and_pick(std::vector<Candidate> cands, const VoxelGrid& region,
                          std::size_t voxels) {
  std::sort(cands.begin(), cands.end(), better);
  const std::size_t refine = std::min<std::size_t>(3, cands.size());
  const LocalOptOptions opt = LocalOptOptions::pattern(10, 1.0, 0.25);
  for (std::size_t i = 0; i < refine; ++i) {
    if (cands[i].mismatch == 0) continue;
    Node3D leaf = Node3D::leaf(cands[i].p);
    TreeEvaluator3D ev(region, leaf);
    optimize_leaves(ev, opt);
    cands[i] = {leaf.primitive, ev.mismatch().total()};
  }
  // A frustum or ellipsoid refined into a near-cylinder or near-sphere fits a digitised shape a
  // few voxels better by chance: the simplest kind within 1 % of the region's volume (+2
  // voxels) of the best wins.
  const Candidate& top = *std::min_element(cands.begin(), cands.end(), better);
  const double tolerance = 0.01 * static_cast<double>(voxels) + 2;
  const Candidate* pick = &top;
  for (std::size_t i = 0; i < refine; ++i)
    if (static_cast<double>(cands[i].mismatch) <= static_cast<double>(top.mismatch) + tolerance &&
        simplicity(cands[i].p.kind) < simplicity(pick->p.kind))
      pick = &cands[i];
  return *pick;
}

}  // namespace

std::optional<RegionMatch3D> match_region3d(const VoxelGrid& region_in, PrimitiveSet3D allowed) {
  if (allowed.empty() || region_in.empty()) return std::nullopt;
  const Moments3D m = compute_moments3d(region_in);
  if (m.voxels == 0) return std::nullopt;
  // Room around the region so that a candidate spilling over its box is charged for it.
  const int lo[3] = {0, 0, 0};
  const int hi[3] = {region_in.nx() - 1, region_in.ny() - 1, region_in.nz() - 1};
  const VoxelGrid region = crop(region_in, lo, hi, 2);
  MomentMatcher matcher(region, m, allowed);
  matcher.add_principal();
  FrustumMoments fm[3];
  for (int t = 0; t < 3; ++t) fm[t] = frustum_moments(kConeRatios[t]);
  for (int ax = 0; ax < 3; ++ax) matcher.add_along(ax, fm);
  std::vector<Candidate> cands = matcher.candidates();
  if (cands.empty()) return std::nullopt;
  const Candidate win = refine_and_pick(std::move(cands), region, m.voxels);
  RegionMatch3D out;
  out.primitive = win.p;
  out.mismatch = win.mismatch;
  const Vec3& lam = matcher.variances();
  const double block = std::sqrt(12 * lam[0]) * std::sqrt(12 * lam[1]) * std::sqrt(12 * lam[2]);
  out.block_volume_ratio = block / m.volume;
  return out;
}

namespace {

struct Solved {
  Node3D tree;
  double score = 0;  // mismatch + k x primitives, summed over the parts
  bool dropped = false;
};

Node3D union_of(std::vector<Node3D> parts) {
  if (parts.size() == 1) return std::move(parts.front());
  return Node3D::op(NodeKind::Union, std::move(parts));
}

class Decomposer3D {
 public:
  explicit Decomposer3D(const DecomposeOptions3D& options)
      : options_(options), start_(std::chrono::steady_clock::now()) {}

  bool out_of_time() const {
    if (options_.cancel && options_.cancel->load(std::memory_order_relaxed)) return true;
    return options_.time_limit > 0 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >
               options_.time_limit;
  }

  // allow_refine: also try the matched primitive with its own errors decomposed (off below
  // such a step, which keeps the work linear in the depth).
  Solved solve(const Region3D& region, int connectivity, int depth, bool allow_refine = true) {
    Solved best = dropped(region);
    if (static_cast<double>(region.volume) <= options_.k) return best;
    // Past its share of the time, a region gets its box or nothing: no matching, no recursion,
    // so the decomposition still ends with a valid tree, and soon.
    if (out_of_time()) return box_or_dropped(region);
    if (auto match = match_region3d(region.mask, options_.primitives)) {
      const double s = static_cast<double>(match->mismatch) + options_.k;
      if (s < best.score) best = {Node3D::leaf(match->primitive), s, false};
      // A perfect match cannot be beaten by a decomposition, which uses at least the box.
      if (match->mismatch == 0) return best;
      if (allow_refine && depth < options_.max_depth && !out_of_time() &&
          static_cast<double>(match->mismatch) < 0.5 * static_cast<double>(region.volume) &&
          static_cast<double>(match->mismatch) > options_.k) {
        Solved refined = solve_matched(region, match->primitive, connectivity, depth, best.score);
        if (refined.score < best.score) best = std::move(refined);
      }
    }
    if (!options_.primitives.has(PrimitiveKind3D::Box) || depth >= options_.max_depth) return best;

    // Box minus the complementary sub-regions (seed 003, Algorithm 1). The region's mask is
    // cropped to its box, so the complement in the box is the inverted mask.
    const VoxelGrid& g = region.mask;
    VoxelGrid complement(g.nx(), g.ny(), g.nz(), g.origin_x(), g.origin_y(), g.origin_z(),
                         g.voxel_size());
    complement.fill();
    complement.subtract(g);
    const double vs = g.voxel_size();
    const Primitive3D box = Primitive3D::box(
        g.origin_x() + 0.5 * g.nx() * vs, g.origin_y() + 0.5 * g.ny() * vs,
        g.origin_z() + 0.5 * g.nz() * vs, g.nx() * vs, g.ny() * vs, g.nz() * vs);
    const int dual = dual_connectivity(connectivity);
    double s = options_.k;
    if (s >= best.score) return best;
    std::vector<Node3D> parts{Node3D::leaf(box)};
    for (const Region3D& sub : connected_regions3d(complement, dual)) {
      // Seed 003's Figure 15: in 3D a sub-region may span its parent's whole box, and then
      // recursing on it would not shrink anything.
      const bool same_box = sub.lo[0] == 0 && sub.lo[1] == 0 && sub.lo[2] == 0 &&
                            sub.hi[0] == g.nx() - 1 && sub.hi[1] == g.ny() - 1 &&
                            sub.hi[2] == g.nz() - 1;
      Solved part = same_box ? solve_split(sub, dual, depth + 1, allow_refine)
                             : solve(sub, dual, depth + 1, allow_refine);
      s += part.score;
      if (s >= best.score) return best;  // already worse: stop early
      if (!part.dropped) parts.push_back(std::move(part.tree));
    }
    best = {parts.size() == 1 ? std::move(parts.front())
                              : Node3D::op(NodeKind::Difference, std::move(parts)),
            s, false};
    return best;
  }

 private:
  Solved box_or_dropped(const Region3D& region) const {
    Solved best = dropped(region);
    if (!options_.primitives.has(PrimitiveKind3D::Box)) return best;
    const VoxelGrid& g = region.mask;  // cropped to the region's box
    const double box_voxels = static_cast<double>(g.nx()) * g.ny() * g.nz();
    const double s = box_voxels - static_cast<double>(region.volume) + options_.k;
    if (s >= best.score) return best;
    const double vs = g.voxel_size();
    best = {Node3D::leaf(Primitive3D::box(g.origin_x() + 0.5 * g.nx() * vs,
                                          g.origin_y() + 0.5 * g.ny() * vs,
                                          g.origin_z() + 0.5 * g.nz() * vs, g.nx() * vs,
                                          g.ny() * vs, g.nz() * vs)),
            s, false};
    return best;
  }

  Solved dropped(const Region3D& region) const {
    Solved d;
    d.dropped = true;
    d.score = static_cast<double>(region.volume);
    return d;
  }

  // The heuristic of seed 003 for a region as large as its parent's box: divide it
  // perpendicular to its longest side and solve the halves' components on their own (each has
  // a strictly smaller box); the whole region may still be matched by one primitive.
  Solved solve_split(const Region3D& region, int connectivity, int depth, bool allow_refine) {
    Solved best = dropped(region);
    if (static_cast<double>(region.volume) <= options_.k) return best;
    if (auto match = match_region3d(region.mask, options_.primitives)) {
      const double s = static_cast<double>(match->mismatch) + options_.k;
      if (s < best.score) best = {Node3D::leaf(match->primitive), s, false};
      if (match->mismatch == 0) return best;
    }
    const VoxelGrid& g = region.mask;
    const int n[3] = {g.nx(), g.ny(), g.nz()};
    const int axis = (n[0] >= n[1] && n[0] >= n[2]) ? 0 : (n[1] >= n[2] ? 1 : 2);
    if (n[axis] < 2 || depth >= options_.max_depth) return best;
    double s = 0;
    std::vector<Node3D> parts;
    for (int half = 0; half < 2; ++half) {
      int lo[3] = {0, 0, 0}, hi[3] = {n[0] - 1, n[1] - 1, n[2] - 1};
      if (half == 0) hi[axis] = n[axis] / 2 - 1;
      else lo[axis] = n[axis] / 2;
      const VoxelGrid piece = crop(g, lo, hi, 0);
      for (const Region3D& sub : connected_regions3d(piece, connectivity)) {
        Solved part = solve(sub, connectivity, depth + 1, allow_refine);
        s += part.score;
        if (s >= best.score) return best;
        if (!part.dropped) parts.push_back(std::move(part.tree));
      }
    }
    if (parts.empty()) return best;
    best = {union_of(std::move(parts)), s, false};
    return best;
  }

  // Beyond seed 003, which only ever subtracts from the bounding box: the matched primitive
  // minus the regions it covers wrongly, plus the regions it misses. A rotated plate with
  // holes is then a rotated box minus cylinders, not its axis-aligned box minus corner wedges.
  // Every piece has fewer voxels than the region (the match's mismatch is under half of it).
  Solved solve_matched(const Region3D& region, const Primitive3D& p, int connectivity, int depth,
                       double bound) {
    Solved out = dropped(region);
    out.score = bound;
    const VoxelGrid& g = region.mask;
    const int lo[3] = {0, 0, 0}, hi[3] = {g.nx() - 1, g.ny() - 1, g.nz() - 1};
    const VoxelGrid r = crop(g, lo, hi, 2);
    VoxelGrid excess(r.nx(), r.ny(), r.nz(), r.origin_x(), r.origin_y(), r.origin_z(), r.voxel_size());
    rasterize(p, excess);
    VoxelGrid missed = r;
    missed.subtract(excess);
    excess.subtract(r);
    double s = options_.k;
    std::vector<Node3D> minus{Node3D::leaf(p)}, plus;
    for (const Region3D& sub : connected_regions3d(excess, dual_connectivity(connectivity))) {
      Solved part = solve(sub, dual_connectivity(connectivity), depth + 1, false);
      s += part.score;
      if (s >= bound) return out;
      if (!part.dropped) minus.push_back(std::move(part.tree));
    }
    for (const Region3D& sub : connected_regions3d(missed, connectivity)) {
      Solved part = solve(sub, connectivity, depth + 1, false);
      s += part.score;
      if (s >= bound) return out;
      if (!part.dropped) plus.push_back(std::move(part.tree));
    }
    Node3D tree = minus.size() == 1 ? std::move(minus.front())
                                    : Node3D::op(NodeKind::Difference, std::move(minus));
    if (!plus.empty()) {
      plus.insert(plus.begin(), std::move(tree));
      tree = Node3D::op(NodeKind::Union, std::move(plus));
    }
    return {std::move(tree), s, false};
  }

  const DecomposeOptions3D& options_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

Node3D decompose3d(const VoxelGrid& target, const DecomposeOptions3D& options) {
  if (target.empty() || target.count() == 0) throw std::invalid_argument("no shape found");
  if (!options.primitives.has(PrimitiveKind3D::Box))
    throw std::invalid_argument("the 3D decomposition needs boxes");
  Decomposer3D dec(options);
  const std::vector<Region3D> components = connected_regions3d(target, options.connectivity);
  std::vector<Node3D> parts;
  const Region3D* largest = &components.front();
  for (const Region3D& comp : components) {
    if (comp.volume > largest->volume) largest = &comp;
    Solved s = dec.solve(comp, options.connectivity, 0);
    if (!s.dropped) parts.push_back(std::move(s.tree));
  }
  if (parts.empty()) {
    // Everything is smaller than a primitive's price: still return the best single primitive
    // for the largest piece, so that the caller always gets a valid tree.
    parts.push_back(Node3D::leaf(match_region3d(largest->mask, options.primitives)->primitive));
  }
  Node3D root = union_of(std::move(parts));
  simplify(root);
  return root;
}

}  // namespace csgfit
