#include "csgfit/seed/boundary_primitives.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "csgfit/features/boundary_curves.h"
#include "csgfit/seed/boundary_rectangles.h"
#include "seed/triangle_frame.h"

namespace csgfit {

namespace {

constexpr double kRadToDeg = 180 / 3.14159265358979323846;
using Corners = std::array<std::array<double, 2>, 3>;

// The corner where lines a and b meet, or nothing when they meet at less than 15 degrees.
std::optional<std::array<double, 2>> corner(const BoundaryLine& a, const BoundaryLine& b) {
  const double det = a.nx * b.ny - a.ny * b.nx;
  if (std::fabs(det) < 0.26) return std::nullopt;
  return std::array<double, 2>{(a.offset * b.ny - b.offset * a.ny) / det,
                               (a.nx * b.offset - b.nx * a.offset) / det};
}

// How far segment l follows its side from corner p to corner q: the overlap, or 0 when less
// than 70 % of the segment lies on the side (it belongs to another edge).
double follows_side(const BoundaryLine& l, const std::array<double, 2>& p, const std::array<double, 2>& q) {
  const double tp = -l.ny * p[0] + l.nx * p[1], tq = -l.ny * q[0] + l.nx * q[1];
  const double lo = std::min(tp, tq), hi = std::max(tp, tq);
  const double overlap = std::min(hi, l.t1) - std::max(lo, l.t0);
  return overlap >= 0.7 * (l.t1 - l.t0) ? overlap : 0;
}

// The triangle three segments bound on the shape's side of each (on the far side for a hole),
// when each segment lies on its side and together they follow a third of its outline.
std::optional<Corners> bounded_triangle(const BoundaryLine* l[3], bool hole, double& followed) {
  Corners v{};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto c = corner(*l[(k + 1) % 3], *l[(k + 2) % 3]);
    if (!c) return std::nullopt;
    v[k] = *c;
  }
  // Every corner a pixel inside the third line's half plane (the shape's side, or the other
  // for a hole): the three half planes meet in this triangle, not in an unbounded wedge.
  const double side = hole ? -1 : 1;
  for (std::size_t k = 0; k < 3; ++k)
    if (side * (l[k]->nx * v[k][0] + l[k]->ny * v[k][1] - l[k]->offset) > -1) return std::nullopt;
  // Unions and cuts hide parts of a drawn triangle's sides: a third of its outline is enough.
  double perimeter = 0;
  followed = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const double f = follows_side(*l[k], v[(k + 1) % 3], v[(k + 2) % 3]);
    if (f <= 0) return std::nullopt;
    followed += f;
    perimeter += std::hypot(v[(k + 1) % 3][0] - v[(k + 2) % 3][0], v[(k + 1) % 3][1] - v[(k + 2) % 3][1]);
  }
  if (followed < perimeter / 3) return std::nullopt;
  return v;
}

// Whether every corner of a lies within 1.5 px of a corner of b (two readings of one triangle
// by nearly collinear segments).
bool same_corners(const Primitive& a, const Primitive& b) {
  const auto va = a.triangle_vertices(), vb = b.triangle_vertices();
  return std::all_of(va.begin(), va.end(), [&](const std::array<double, 2>& p) {
    return std::any_of(vb.begin(), vb.end(), [&](const std::array<double, 2>& q) {
      return std::hypot(p[0] - q[0], p[1] - q[1]) < 1.5;
    });
  });
}

Primitive triangle_through(const Corners& c) {
  const double v[3][2] = {{c[0][0], c[0][1]}, {c[1][0], c[1][1]}, {c[2][0], c[2][1]}};
  const TriangleFrame f = triangle_frame(v);
  return Primitive::triangle(f.cx, f.cy, f.w, f.h, f.angle * kRadToDeg, f.apex);
}

// The triangles three boundary segments bound: inside the shape but for 35 % of their area
// (outside it for holes; the rest may be cut away by holes), at least 12 px, those whose
// outline the contour follows furthest first.
void boundary_triangles(const Bitmap& target, const std::vector<BoundaryLine>& lines, BoundaryPrimitives& out) {
  std::vector<std::pair<double, Primitive>> found[2];
  Bitmap raster(target.width(), target.height());
  for (std::size_t i = 0; i < lines.size(); ++i)
    for (std::size_t j = i + 1; j < lines.size(); ++j)
      for (std::size_t k = j + 1; k < lines.size(); ++k)
        for (int hole = 0; hole < 2; ++hole) {
          const BoundaryLine* l[3] = {&lines[i], &lines[j], &lines[k]};
          double followed = 0;
          const auto corners = bounded_triangle(l, hole == 1, followed);
          if (!corners) continue;
          const Primitive t = triangle_through(*corners);
          if (t.area() < 12) continue;
          rasterize(t, raster);
          const std::size_t drawn = raster.count();
          if (hole == 0) raster.subtract(target); else raster &= target;
          if (static_cast<double>(raster.count()) > 0.35 * static_cast<double>(drawn)) continue;
          found[hole].emplace_back(followed, t);
        }
  for (int hole = 0; hole < 2; ++hole) {
    std::stable_sort(found[hole].begin(), found[hole].end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<Primitive> kept;
    for (const auto& candidate : found[hole]) {
      if (kept.size() == 24) break;
      if (std::none_of(kept.begin(), kept.end(),
                       [&](const Primitive& k) { return same_corners(k, candidate.second); }))
        kept.push_back(candidate.second);
    }
    (hole ? out.holes : out.positives).insert((hole ? out.holes : out.positives).end(), kept.begin(), kept.end());
  }
}

// The discs and holes the contour's arcs lie on, and its ellipses (a circle as a round
// ellipse when only ellipses are allowed).
void boundary_round(const Contour& contour, const std::vector<BoundaryLine>& lines, bool circles,
                    bool ellipses, BoundaryPrimitives& out) {
  const std::vector<BoundaryArc> arcs = boundary_arcs(contour);
  for (const BoundaryArc& a : arcs) {
    const Primitive p = circles ? Primitive::circle(a.cx, a.cy, a.r)
                                : Primitive::ellipse(a.cx, a.cy, a.r, a.r, 0);
    (a.hole ? out.holes : out.positives).push_back(p);
  }
  if (!ellipses) return;
  for (const BoundaryEllipse& e : boundary_ellipses(contour, arcs, lines)) {
    // A circle read a little squashed is the circle already proposed.
    const bool seen = std::any_of(arcs.begin(), arcs.end(), [&](const BoundaryArc& a) {
      return a.hole == e.hole && std::hypot(a.cx - e.cx, a.cy - e.cy) < 1.5 &&
             std::fabs((e.rx + e.ry) / 2 - a.r) < 0.1 * a.r;
    });
    if (!seen)
      (e.hole ? out.holes : out.positives).push_back(Primitive::ellipse(e.cx, e.cy, e.rx, e.ry, e.angle));
  }
}

// The pixels the holes read so far cut from the shape.
Bitmap drilled_by(const std::vector<Primitive>& holes, int width, int height) {
  Bitmap out(width, height);
  for (const Primitive& h : holes) rasterize_into(h, out);
  return out;
}

}  // namespace

BoundaryPrimitives boundary_primitives(const Bitmap& target, const PrimitiveSet& allowed) {
  BoundaryPrimitives out;
  const Contour contour = contour_of(target);  // read once, by every reading below
  const std::vector<BoundaryLine> lines = boundary_lines(contour);
  if (allowed.has(PrimitiveKind::Triangle)) boundary_triangles(target, lines, out);
  const bool circles = allowed.has(PrimitiveKind::Circle), ellipses = allowed.has(PrimitiveKind::Ellipse);
  if (circles || ellipses) boundary_round(contour, lines, circles, ellipses, out);
  if (allowed.has(PrimitiveKind::Rectangle)) {
    // Read last, so that a plate may span the holes its arcs and edges show.
    const Bitmap drilled = drilled_by(out.holes, target.width(), target.height());
    const std::vector<Primitive> plates = boundary_rectangles(target, 48, 0.03, &drilled);
    out.positives.insert(out.positives.begin(), plates.begin(), plates.end());
    // The background's rectangles are the slots and notches cut from the shape.
    const std::vector<Primitive> slots = boundary_rectangles(target.inverted(), 16);
    out.holes.insert(out.holes.begin(), slots.begin(), slots.end());
  }
  return out;
}

}  // namespace csgfit
