#include "csgfit/refine/contour_fit2d.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "refine/least_squares.h"
#include "refine/moves2d.h"

namespace csgfit {

namespace {

constexpr double kBlur = 1.0;  // the contour's Gaussian, pixels (subpixel_contour)

// The blur moves the contour of a curved edge towards its centre of curvature by
// kBlur^2 * curvature / 2 (for a disc of radius r: sigma^2 / 2r, inwards; for a hole the same,
// towards the hole's centre): the distance a point of an exact edge has from p's boundary.
double blur_offset(const Primitive& p, const ContourPoint& q) {
  if (p.kind == PrimitiveKind::Circle) return -0.5 * kBlur * kBlur / std::max(0.5 * p.w, 1.0);
  if (p.kind != PrimitiveKind::Ellipse) return 0;
  const double a = std::max(0.5 * p.w, 1.0), b = std::max(0.5 * p.h, 1.0);
  const double t = p.angle * 3.14159265358979323846 / 180, c = std::cos(t), s = std::sin(t);
  const double x = c * (q.x - p.cx) + s * (q.y - p.cy), y = -s * (q.x - p.cx) + c * (q.y - p.cy);
  const double u = std::atan2(y / b, x / a);
  const double g = a * a * std::sin(u) * std::sin(u) + b * b * std::cos(u) * std::cos(u);
  return -0.5 * kBlur * kBlur * a * b / (g * std::sqrt(g));
}

double residual(const Primitive& p, const ContourPoint& q) {
  return p.signed_distance(q.x, q.y) - blur_offset(p, q);
}

// Whether p's edge near q runs as the contour does there (normals within 30 degrees either
// way round: a cut's edge faces the other way).
bool runs_along(const Primitive& p, const ContourPoint& q) {
  constexpr double h = 0.05;
  const double gx = p.signed_distance(q.x + h, q.y) - p.signed_distance(q.x - h, q.y);
  const double gy = p.signed_distance(q.x, q.y + h) - p.signed_distance(q.x, q.y - h);
  const double len = std::hypot(gx, gy);
  return len > 0 && std::fabs(gx * q.nx + gy * q.ny) >= 0.866 * len;
}

}  // namespace

std::size_t refine_to_contour(TreeEvaluator& ev, const std::vector<ContourPoint>& contour,
                              const BoundaryFitOptions& options) {
  const std::size_t n = ev.leaf_count();
  std::size_t changed = 0;
  if (n == 0 || contour.empty()) return 0;
  for (int round = 0; round < options.rounds; ++round) {
    std::vector<std::vector<const ContourPoint*>> assigned(n);
    for (const ContourPoint& q : contour) {
      std::size_t best = n;
      double best_d = options.inlier;
      for (std::size_t i = 0; i < n; ++i) {
        const double d = std::fabs(ev.leaf(i).signed_distance(q.x, q.y));
        if (d < best_d) best_d = d, best = i;
      }
      if (best < n && runs_along(ev.leaf(best), q)) assigned[best].push_back(&q);
    }
    std::size_t round_changes = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::chrono::steady_clock::now() >= options.deadline) return changed;
      Moves2D::Param params[Moves2D::kMaxParams];
      const int np = Moves2D::params_of(ev.leaf(i), LocalOptOptions{}, params);
      if (assigned[i].size() < static_cast<std::size_t>(3 * np)) continue;
      const Primitive refined = least_squares::fit_to_points(Moves2D{}, ev.leaf(i), assigned[i],
                                                             1.0, options.iterations, residual);
      if (refined == ev.leaf(i)) continue;
      if (ev.try_leaf(i, refined).total() > ev.mismatch().total()) continue;
      ev.leaf(i) = refined;
      ev.update_leaf(i);
      ++round_changes;
    }
    changed += round_changes;
    if (round_changes == 0) break;
  }
  return changed;
}

}  // namespace csgfit
