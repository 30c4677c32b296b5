#include "csgfit/seed/decompose2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/refine/local_opt.h"
#include "seed/triangle_frame.h"

namespace csgfit {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;

// The 2D triangle with these vertices.
Primitive triangle_from_vertices(const double v[3][2]) {
  const TriangleFrame f = triangle_frame(v);
  return Primitive::triangle(f.cx, f.cy, f.w, f.h, f.angle * kRadToDeg, f.apex);
}

std::size_t mismatch_with(const Primitive& p, const Bitmap& region, Bitmap& scratch) {
  rasterize(p, scratch);
  return count_xor(scratch, region);
}

double boundary_deviation(const Primitive& p, const std::vector<std::pair<int, int>>& boundary,
                          int height) {
  if (boundary.empty()) return 0;
  double sum = 0;
  for (auto [c, r] : boundary) {
    const double d = p.signed_distance(c + 0.5, height - r - 0.5);
    sum += d * d;
  }
  const double perimeter = static_cast<double>(boundary.size());
  return sum / (perimeter * perimeter);
}

}  // namespace

std::optional<RegionMatch> match_region(const Bitmap& region, PrimitiveSet allowed) {
  const Moments m = compute_moments(region);
  if (m.area <= 0 || allowed.empty()) return std::nullopt;
  Bitmap scratch(region.width(), region.height());
  struct Candidate {
    Primitive p;
    std::size_t mismatch;
  };
  std::vector<Candidate> candidates;
  auto add = [&](const Primitive& p) {
    candidates.push_back({p, mismatch_with(p, region, scratch)});
  };
  const double l1 = m.lambda1, l2 = std::max(m.lambda2, 1.0 / 12.0);
  // Moment equations of each shape (variance along a principal axis):
  // rectangle of side a: a^2/12; ellipse of semi-axis r: r^2/4.
  if (allowed.has(PrimitiveKind::Rectangle))
    add(Primitive::rectangle(m.cx, m.cy, std::sqrt(12 * l1), std::sqrt(12 * l2), m.angle));
  if (allowed.has(PrimitiveKind::Ellipse))
    add(Primitive::ellipse(m.cx, m.cy, 2 * std::sqrt(l1), 2 * std::sqrt(l2), m.angle));
  if (allowed.has(PrimitiveKind::Circle))
    add(Primitive::circle(m.cx, m.cy, 2 * std::sqrt(0.5 * (l1 + l2))));
  if (allowed.has(PrimitiveKind::Triangle)) {
    // Every triangle is an affine image of the equilateral one, whose covariance is I/8 for
    // circumradius 1. The triangles with this region's covariance are therefore
    // sqrt(8) * Sigma^(1/2) * R(phi) * equilateral: a one-parameter family in phi, which holds
    // the isosceles and right-angled triangles of seed 003. Scan phi over its 120 deg period.
    const double th = m.angle * kDegToRad;
    const double e1x = std::cos(th), e1y = std::sin(th);
    const double s1 = std::sqrt(8 * l1), s2 = std::sqrt(8 * l2);
    Candidate best{Primitive{}, static_cast<std::size_t>(-1)};
    for (int step = 0; step < 40; ++step) {
      const double phi = step * 3.0 * kDegToRad;
      double v[3][2];
      for (int i = 0; i < 3; ++i) {
        const double a = phi + kPi / 2 + i * 2 * kPi / 3;
        // In the principal frame: scale the unit-circumradius vertex by the principal sizes.
        const double px = s1 * std::cos(a), py = s2 * std::sin(a);
        v[i][0] = m.cx + e1x * px - e1y * py;
        v[i][1] = m.cy + e1y * px + e1x * py;
      }
      const Primitive t = triangle_from_vertices(v);
      const std::size_t mm = mismatch_with(t, region, scratch);
      if (mm < best.mismatch) best = {t, mm};
    }
    candidates.push_back(best);
  }
  if (candidates.empty()) return std::nullopt;
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.mismatch < b.mismatch; });
  // Refine the two most promising against the region: moments of a digitised shape are only
  // approximately those of the continuous one.
  const std::size_t refine = std::min<std::size_t>(2, candidates.size());
  const LocalOptOptions opt = LocalOptOptions::pattern(12, 1.0, 0.25);
  for (std::size_t i = 0; i < refine; ++i) {
    Node leaf = Node::leaf(candidates[i].p);
    TreeEvaluator ev(region, leaf);
    optimize_leaves(ev, opt);
    candidates[i] = {leaf.primitive, ev.mismatch().total()};
  }
  const auto best = std::min_element(
      candidates.begin(), candidates.end(),
      [](const Candidate& a, const Candidate& b) { return a.mismatch < b.mismatch; });
  RegionMatch out;
  out.primitive = best->p;
  out.mismatch = best->mismatch;
  out.boundary_deviation = boundary_deviation(best->p, boundary_pixels(region), region.height());
  return out;
}

namespace {

struct Solved {
  Node tree;
  double score = 0;  // excess + uncovered + k x primitives, summed over the parts
  bool dropped = false;
};

class Decomposer {
 public:
  Decomposer(const Bitmap& target, const DecomposeOptions& options)
      : target_(target), options_(options) {}

  Solved solve(const Region& region, int connectivity, int depth) {
    const double area = static_cast<double>(region.area);
    Solved best;
    best.dropped = true;
    best.score = area;  // leaving the region out costs its pixels
    // Anything smaller than one primitive's price is cheaper left out.
    if (area <= options_.k) return best;

    if (auto match = match_region(region.mask, options_.primitives)) {
      const double s = static_cast<double>(match->mismatch) + options_.k;
      if (s < best.score) best = {Node::leaf(match->primitive), s, false};
      // A perfect match cannot be beaten by a decomposition, which uses at least the box.
      if (match->mismatch == 0) return best;
    }
    if (!options_.primitives.has(PrimitiveKind::Rectangle) || depth >= options_.max_depth)
      return best;

    // Box minus the complementary sub-regions (seed 003, Algorithm 1).
    const int h = target_.height();
    Bitmap complement(target_.width(), h);
    for (int r = region.row_min; r <= region.row_max; ++r)
      complement.set_span(r, region.col_min, region.col_max + 1);
    complement.subtract(region.mask);
    const Primitive box = Primitive::rectangle(
        0.5 * (region.col_min + region.col_max + 1), h - 0.5 * (region.row_min + region.row_max + 1),
        region.col_max - region.col_min + 1, region.row_max - region.row_min + 1, 0);
    const int dual = connectivity == 4 ? 8 : 4;
    std::vector<Region> subs = connected_regions(complement, dual, region.col_min, region.row_min,
                                                 region.col_max, region.row_max);
    double s = options_.k;
    std::vector<Node> holes;
    for (const Region& sub : subs) {
      // In 2D a sub-region's box is strictly smaller (Proposition 2); should digitisation ever
      // break that, do not recurse on it, which keeps the recursion finite.
      const bool same_box = sub.col_min == region.col_min && sub.col_max == region.col_max &&
                            sub.row_min == region.row_min && sub.row_max == region.row_max;
      Solved part = same_box ? solve_leaf_only(sub) : solve(sub, dual, depth + 1);
      s += part.score;
      if (s >= best.score) return best;  // already worse: stop early
      if (!part.dropped) holes.push_back(std::move(part.tree));
    }
    if (s < best.score) {
      std::vector<Node> children;
      children.push_back(Node::leaf(box));
      for (Node& hnode : holes) children.push_back(std::move(hnode));
      Node tree = children.size() == 1 ? std::move(children.front())
                                       : Node::op(NodeKind::Difference, std::move(children));
      best = {std::move(tree), s, false};
    }
    return best;
  }

 private:
  Solved solve_leaf_only(const Region& region) {
    Solved best;
    best.dropped = true;
    best.score = static_cast<double>(region.area);
    if (auto match = match_region(region.mask, options_.primitives)) {
      const double s = static_cast<double>(match->mismatch) + options_.k;
      if (s < best.score) best = {Node::leaf(match->primitive), s, false};
    }
    return best;
  }

  const Bitmap& target_;
  const DecomposeOptions& options_;
};

}  // namespace

Node decompose(const Bitmap& target, const DecomposeOptions& options) {
  if (target.count() == 0) throw std::invalid_argument("no shape found");
  Decomposer dec(target, options);
  std::vector<Region> components = connected_regions(target, 4);
  std::vector<Node> parts;
  const Region* largest = &components.front();
  for (const Region& comp : components) {
    if (comp.area > largest->area) largest = &comp;
    Solved s = dec.solve(comp, 4, 0);
    if (!s.dropped) parts.push_back(std::move(s.tree));
  }
  if (parts.empty()) {
    // Everything is smaller than a primitive's price: still return the best single primitive
    // for the largest piece, so that the caller always gets a valid tree.
    PrimitiveSet set = options.primitives;
    auto match = match_region(largest->mask, set.empty() ? PrimitiveSet::all() : set);
    parts.push_back(Node::leaf(match->primitive));
  }
  Node root = parts.size() == 1 ? std::move(parts.front()) : Node::op(NodeKind::Union, std::move(parts));
  simplify(root);
  return root;
}

}  // namespace csgfit
