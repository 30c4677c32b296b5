#include "csgfit/optimise/snap2d.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "csgfit/model/shared_dimensions.h"
#include "csgfit/refine/local_opt.h"

namespace csgfit {

namespace {

// Whether no pixel centre lies on p's boundary. Round numbers put edges exactly on pixel
// centres (a 2-pixel-wide square centred on a half pixel), where our closed inside test and
// OpenSCAD's polygon rasterisation may disagree; such a snap is not worth keeping.
bool free_of_ties(const Primitive& p, const Bitmap& raster) {
  constexpr double kEps = 1e-3;
  Primitive shrunk = p;
  shrunk.w -= 2 * kEps;
  shrunk.h -= 2 * kEps;
  Bitmap inner(raster.width(), raster.height());
  rasterize(shrunk, inner);
  if (inner != raster) return false;
  Primitive grown = p;
  grown.w += 2 * kEps;
  grown.h += 2 * kEps;
  rasterize(grown, inner);
  return inner == raster;
}


// Near-equal values made one where that costs at most the budget: the repeated holes of a
// design, its equal bars and concentric circles. Whatever a group decides is kept out of the
// later rounding of single values, which would tell the members apart again.
class GroupSnapper {
 public:
  GroupSnapper(TreeEvaluator& ev, double& budget) : ev_(ev), budget_(budget) {}

  bool locked(std::size_t leaf, DimensionField f) const { return locked_.count({leaf, f}) > 0; }
  std::size_t snapped() const { return snapped_; }

  void concentric() {
    std::vector<DimensionUse> round;
    for (std::size_t i = 0; i < ev_.leaf_count(); ++i)
      if (is_round(ev_.leaf(i).kind)) round.push_back({i, DimensionField::CentreX});
    // Centres within a pixel (or 5 % of the smaller radius) are one axis.
    auto near = [&](const DimensionUse& a, const DimensionUse& b) {
      const Primitive &p = ev_.leaf(a.leaf), &q = ev_.leaf(b.leaf);
      const double tol = std::max(1.0, 0.05 * std::min(small_radius(p), small_radius(q)));
      return std::hypot(p.cx - q.cx, p.cy - q.cy) <= tol;
    };
    for (auto g : clusters(round, near)) {
      snap_group(g);
      for (DimensionUse& u : g) u.field = DimensionField::CentreY;
      snap_group(g);
    }
  }

  void equal_sizes() {
    std::vector<DimensionUse> radii, sides;
    for (std::size_t i = 0; i < ev_.leaf_count(); ++i) {
      const PrimitiveKind k = ev_.leaf(i).kind;
      if (k == PrimitiveKind::Circle) radii.push_back({i, DimensionField::Radius});
      if (k != PrimitiveKind::Rectangle) continue;
      sides.push_back({i, DimensionField::Width});
      sides.push_back({i, DimensionField::Height});
    }
    // Within 4 %: a designer's equal holes, not a small and a large one.
    auto near = [&](const DimensionUse& a, const DimensionUse& b) {
      const double x = value(a), y = value(b);
      return std::fabs(x - y) <= 0.04 * std::max(x, y);
    };
    for (const auto& members : {radii, sides})
      for (const auto& g : clusters(members, near)) snap_group(g);
  }

 private:
  using Uses = std::vector<DimensionUse>;

  static bool is_round(PrimitiveKind k) {
    return k == PrimitiveKind::Circle || k == PrimitiveKind::Ellipse;
  }
  static double small_radius(const Primitive& p) { return 0.5 * std::min(p.w, p.h); }
  double value(const DimensionUse& u) const { return field_value(ev_.leaf(u.leaf), u.field); }

  static void set_field(Primitive& p, DimensionField f, double v) {
    switch (f) {
      case DimensionField::CentreX: p.cx = v; break;
      case DimensionField::CentreY: p.cy = v; break;
      case DimensionField::Width: p.w = v; break;
      case DimensionField::Height: p.h = v; break;
      case DimensionField::Radius: p.w = p.h = 2 * v; break;
      case DimensionField::Length: break;  // 3D only
    }
  }

  // Groups of two or more, each member near the group's first (so a chain cannot drift).
  template <typename Near>
  static std::vector<Uses> clusters(const Uses& items, Near near) {
    std::vector<Uses> out;
    std::vector<bool> taken(items.size(), false);
    for (std::size_t a = 0; a < items.size(); ++a) {
      if (taken[a]) continue;
      Uses g{items[a]};
      for (std::size_t b = a + 1; b < items.size(); ++b)
        if (!taken[b] && near(items[a], items[b])) g.push_back(items[b]), taken[b] = true;
      if (g.size() > 1) out.push_back(std::move(g));
    }
    return out;
  }

  // The common values worth trying, roundest first: ties in the mismatch go to the rounder one.
  std::vector<double> candidates(const Uses& g) const {
    double lo = value(g.front()), hi = lo, sum = 0;
    for (const DimensionUse& u : g) {
      const double v = value(u);
      lo = std::min(lo, v), hi = std::max(hi, v), sum += v;
    }
    const double mean = sum / static_cast<double>(g.size());
    std::vector<double> out{std::round(mean * 2) / 2, std::round(mean * 4) / 4};
    for (const DimensionUse& u : g) out.push_back(value(u));
    for (double v = lo - 0.25; v <= hi + 0.25; v += 1.0 / 16) out.push_back(v);
    return out;
  }

  void set_all(const Uses& g, double v) {
    for (const DimensionUse& u : g) set_field(ev_.leaf(u.leaf), u.field, v);
    for (const DimensionUse& u : g) ev_.update_leaf(u.leaf);
  }

  void snap_group(const Uses& g) {
    const bool is_size =
        g.front().field != DimensionField::CentreX && g.front().field != DimensionField::CentreY;
    std::vector<Primitive> original;
    for (const DimensionUse& u : g) original.push_back(ev_.leaf(u.leaf));
    const double before = static_cast<double>(ev_.mismatch().total());
    double best_cost = budget_;
    std::optional<double> best;
    for (double v : candidates(g)) {
      if (is_size && !(v > 0)) continue;
      set_all(g, v);
      const double cost = static_cast<double>(ev_.mismatch().total()) - before;
      if ((cost < best_cost || (!best && cost <= best_cost)) && members_free_of_ties(g))
        best_cost = cost, best = v;
    }
    for (std::size_t k = 0; k < g.size(); ++k) ev_.leaf(g[k].leaf) = original[k];
    for (const DimensionUse& u : g) ev_.update_leaf(u.leaf);
    if (!best) return;
    set_all(g, *best);
    budget_ -= std::max(0.0, best_cost);
    for (const DimensionUse& u : g) locked_.insert({u.leaf, u.field});
    ++snapped_;
  }

  bool members_free_of_ties(const Uses& g) const {
    for (const DimensionUse& u : g)
      if (!free_of_ties(ev_.leaf(u.leaf), ev_.leaf_mask(u.leaf))) return false;
    return true;
  }

  TreeEvaluator& ev_;
  double& budget_;
  std::set<std::pair<std::size_t, DimensionField>> locked_;
  std::size_t snapped_ = 0;
};

double round_to(double v, double step) { return std::round(v / step) * step; }

constexpr double kStraightening = 0.5;  // degrees

// Shapes and angles: a round ellipse becomes a circle, angles go to 15 degrees or whole ones,
// a triangle's apex to seed 003's isosceles and right-angled ones. An angle within
// kStraightening of a multiple of 15 degrees is a wobble of the drawing or the scan, not a
// designed angle: it snaps whatever it costs.
template <typename Attempt>
void snap_shapes(TreeEvaluator& ev, PrimitiveSet allowed, Attempt& attempt) {
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive p = ev.leaf(i);
    if (p.kind == PrimitiveKind::Ellipse && allowed.has(PrimitiveKind::Circle) &&
        std::fabs(p.w - p.h) < 0.1 * std::max(p.w, p.h)) {
      attempt(i, Primitive::circle(p.cx, p.cy, 0.25 * (p.w + p.h)), true, false);
    }
    if (ev.leaf(i).kind != PrimitiveKind::Circle) {
      Primitive q = ev.leaf(i);
      q.angle = round_to(q.angle, 15.0);
      const bool wobble = std::fabs(q.angle - ev.leaf(i).angle) <= kStraightening;
      if (!attempt(i, q, true, false, wobble)) {
        q = ev.leaf(i);
        q.angle = round_to(q.angle, 1.0);
        attempt(i, q, true, false);
      }
    }
    const PrimitiveKind kind = ev.leaf(i).kind;
    const double quarters = ev.leaf(i).angle / 90.0;
    if ((kind == PrimitiveKind::Rectangle || kind == PrimitiveKind::Ellipse) && quarters != 0 &&
        quarters == std::round(quarters)) {
      // Turned by quarter turns, a centred shape is itself with its sides swapped or not: a
      // designer writes it unturned.
      Primitive q = ev.leaf(i);
      if (std::fmod(quarters, 2.0) != 0) std::swap(q.w, q.h);
      q.angle = 0;
      attempt(i, q, true, true);
    }
    if (ev.leaf(i).kind == PrimitiveKind::Triangle) {
      Primitive q = ev.leaf(i);
      q.apex = round_to(q.apex, 1.0);
      if (!attempt(i, q, true, false)) {
        q = ev.leaf(i);
        q.apex = round_to(q.apex, 0.05);
        attempt(i, q, true, false);
      }
    }
  }
}

// Positions and sizes to half pixels, one at a time, after every shape, angle and group had
// its turn at the budget, and only where they cost no pixel; what a group made equal stays as
// it is.
template <typename Attempt>
void snap_round_numbers(TreeEvaluator& ev, const GroupSnapper& groups, Attempt& attempt) {
  constexpr DimensionField kFields[] = {DimensionField::CentreX, DimensionField::CentreY,
                                        DimensionField::Width, DimensionField::Height};
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const bool any_locked = std::any_of(std::begin(kFields), std::end(kFields), [&](auto f) {
      return groups.locked(i, f) || groups.locked(i, DimensionField::Radius);
    });
    // An axis-aligned rectangle is best dimensioned with its edges on pixel boundaries: round
    // numbers in the drawing, and no pixel centre on an edge.
    const Primitive r = ev.leaf(i);
    if (r.kind == PrimitiveKind::Rectangle && std::fmod(r.angle, 90.0) == 0 && !any_locked) {
      const bool turned = std::fmod(r.angle, 180.0) != 0;
      const double hx = 0.5 * (turned ? r.h : r.w), hy = 0.5 * (turned ? r.w : r.h);
      const double x0 = std::round(r.cx - hx), x1 = std::round(r.cx + hx);
      const double y0 = std::round(r.cy - hy), y1 = std::round(r.cy + hy);
      if (x1 > x0 && y1 > y0) {
        Primitive q = r;
        q.cx = 0.5 * (x0 + x1);
        q.cy = 0.5 * (y0 + y1);
        (turned ? q.h : q.w) = x1 - x0;
        (turned ? q.w : q.h) = y1 - y0;
        attempt(i, q, false, false);
      }
    }
    for (int param = 0; param < 4; ++param) {
      Primitive q = ev.leaf(i);
      const bool circle = q.kind == PrimitiveKind::Circle;
      if (circle && param == 3) continue;
      const DimensionField f = circle && param == 2 ? DimensionField::Radius : kFields[param];
      if (groups.locked(i, f)) continue;
      double* v = param == 0 ? &q.cx : param == 1 ? &q.cy : param == 2 ? &q.w : &q.h;
      *v = round_to(*v, 0.5);
      if (circle) q.h = q.w;
      // Nothing is re-fitted: a re-fit would move the value off the grid again.
      attempt(i, q, false, false);
    }
  }
}

}  // namespace

DesignSnaps snap_to_design_values(TreeEvaluator& ev, PrimitiveSet allowed, double pixel_budget) {
  DesignSnaps out;
  double budget = pixel_budget;
  // Keeps `trial` (after re-fitting what it leaves free) if that costs at most the budget left,
  // or whatever it costs when it straightens a near-right angle.
  LocalOptOptions refit = LocalOptOptions::pattern(20, 0.5, 0.0625);
  auto attempt = [&](std::size_t leaf, const Primitive& trial, bool angle_fixed, bool size_fixed,
                     bool straightens = false) {
    if (trial == ev.leaf(leaf)) return false;
    const Primitive original = ev.leaf(leaf);
    const double before = static_cast<double>(ev.mismatch().total());
    ev.leaf(leaf) = trial;
    ev.update_leaf(leaf);
    refit.move_orientation = !angle_fixed;
    refit.move_sizes = !size_fixed;
    if (angle_fixed || size_fixed) optimize_leaves(ev, refit, {leaf});
    const double after = static_cast<double>(ev.mismatch().total());
    const double cost = std::max(0.0, after - before);
    if ((!straightens && cost > budget) || !free_of_ties(ev.leaf(leaf), ev.leaf_mask(leaf))) {
      ev.leaf(leaf) = original;
      ev.update_leaf(leaf);
      return false;
    }
    if (straightens) {
      out.straightening_cost += cost;
    } else {
      budget -= cost;
    }
    ++out.snapped;
    return true;
  };
  snap_shapes(ev, allowed, attempt);
  GroupSnapper groups(ev, budget);
  groups.concentric();
  groups.equal_sizes();
  // A round number is a convenience, not the design: it is taken only where it costs nothing.
  budget = 0;
  snap_round_numbers(ev, groups, attempt);
  out.snapped += groups.snapped();
  return out;
}

std::size_t untie(TreeEvaluator& ev) {
  constexpr double kNudge = 0.005;  // pixels: far above the .scad writer's rounding
  std::size_t nudged = 0;
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive p = ev.leaf(i);
    if (free_of_ties(p, ev.leaf_mask(i))) continue;
    // Growing keeps every centre that is on the boundary inside, as the solver counted it, and
    // moves the boundary off it; shrinking is the fallback when growing would take in others.
    for (double d : {kNudge, -kNudge}) {
      Primitive q = p;
      q.w += 2 * d;
      q.h += 2 * d;
      Bitmap raster(ev.leaf_mask(i).width(), ev.leaf_mask(i).height());
      rasterize(q, raster);
      if (raster == ev.leaf_mask(i) && free_of_ties(q, raster)) {
        ev.leaf(i) = q;
        ev.update_leaf(i);
        ++nudged;
        break;
      }
    }
  }
  return nudged;
}

}  // namespace csgfit
