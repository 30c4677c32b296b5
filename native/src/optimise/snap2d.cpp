#include "csgfit/optimise/snap2d.h"

#include <algorithm>
#include <cmath>

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

}  // namespace

std::size_t snap_to_design_values(TreeEvaluator& ev, PrimitiveSet allowed, double pixel_budget) {
  std::size_t snapped = 0;
  double budget = pixel_budget;
  // Keeps `trial` (after re-fitting what it leaves free) if that costs at most the budget left.
  LocalOptOptions refit = LocalOptOptions::pattern(20, 0.5, 0.0625);
  auto attempt = [&](std::size_t leaf, const Primitive& trial, bool angle_fixed, bool size_fixed) {
    if (trial == ev.leaf(leaf)) return false;
    const Primitive original = ev.leaf(leaf);
    const double before = static_cast<double>(ev.mismatch().total());
    ev.leaf(leaf) = trial;
    ev.update_leaf(leaf);
    refit.move_orientation = !angle_fixed;
    refit.move_sizes = !size_fixed;
    if (angle_fixed || size_fixed) optimize_leaves(ev, refit, {leaf});
    const double after = static_cast<double>(ev.mismatch().total());
    if (after - before > budget || !free_of_ties(ev.leaf(leaf), ev.leaf_mask(leaf))) {
      ev.leaf(leaf) = original;
      ev.update_leaf(leaf);
      return false;
    }
    budget -= std::max(0.0, after - before);
    ++snapped;
    return true;
  };
  auto round_to = [](double v, double step) { return std::round(v / step) * step; };
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive p = ev.leaf(i);
    if (p.kind == PrimitiveKind::Ellipse && allowed.has(PrimitiveKind::Circle) &&
        std::fabs(p.w - p.h) < 0.1 * std::max(p.w, p.h)) {
      attempt(i, Primitive::circle(p.cx, p.cy, 0.25 * (p.w + p.h)), true, false);
    }
    if (ev.leaf(i).kind != PrimitiveKind::Circle) {
      Primitive q = ev.leaf(i);
      q.angle = round_to(q.angle, 15.0);
      if (!attempt(i, q, true, false)) {
        q = ev.leaf(i);
        q.angle = round_to(q.angle, 1.0);
        attempt(i, q, true, false);
      }
    }
    if (ev.leaf(i).kind == PrimitiveKind::Triangle) {
      Primitive q = ev.leaf(i);
      // Seed 003's isosceles (apex 0) and right-angled (apex +-1) triangles, else a tidy ratio.
      q.apex = round_to(q.apex, 1.0);
      if (!attempt(i, q, true, false)) {
        q = ev.leaf(i);
        q.apex = round_to(q.apex, 0.05);
        attempt(i, q, true, false);
      }
    }
  }
  // Positions and sizes only after every shape and angle had its turn at the budget.
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    // An axis-aligned rectangle is best dimensioned with its edges on pixel boundaries: round
    // numbers in the drawing, and no pixel centre on an edge.
    const Primitive r = ev.leaf(i);
    if (r.kind == PrimitiveKind::Rectangle && std::fmod(r.angle, 90.0) == 0) {
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
      double* v = param == 0 ? &q.cx : param == 1 ? &q.cy : param == 2 ? &q.w : &q.h;
      if (q.kind == PrimitiveKind::Circle && param == 3) continue;
      *v = round_to(*v, 0.5);
      if (q.kind == PrimitiveKind::Circle) q.h = q.w;
      // Positions and sizes are snapped last and one at a time, with nothing re-fitted: a
      // re-fit would move them off the grid again.
      attempt(i, q, false, false);
    }
  }
  return snapped;
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
