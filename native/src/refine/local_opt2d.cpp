#include "csgfit/refine/local_opt2d.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace csgfit {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

enum class Param { X, Y, W, H, Angle, Apex };

// The parameters worth moving for a kind (a circle has one size and no orientation).
int params_of(PrimitiveKind kind, const LocalOptOptions& o, Param out[6]) {
  int n = 0;
  out[n++] = Param::X;
  out[n++] = Param::Y;
  if (o.move_sizes) out[n++] = Param::W;
  if (kind != PrimitiveKind::Circle) {
    if (o.move_sizes) out[n++] = Param::H;
    if (o.move_angles) out[n++] = Param::Angle;
  }
  if (kind == PrimitiveKind::Triangle && o.move_angles) out[n++] = Param::Apex;
  return n;
}

void move(Primitive& p, Param param, double step) {
  switch (param) {
    case Param::X: p.cx += step; break;
    case Param::Y: p.cy += step; break;
    case Param::W:
      p.w += step;
      if (p.kind == PrimitiveKind::Circle) p.h = p.w;
      break;
    case Param::H: p.h += step; break;
    case Param::Angle: {
      // Turn by the angle that moves the furthest point by about `step` pixels, at most 15 deg.
      const double reach = std::max(0.5 * std::max(p.w, p.h), 1.0);
      const double deg = std::clamp(step / reach * kRadToDeg, -15.0, 15.0);
      p.angle += deg;
      break;
    }
    case Param::Apex: p.apex += step / std::max(0.5 * p.w, 1.0); break;
  }
}

}  // namespace

std::size_t optimize_leaves(TreeEvaluator& ev, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices) {
  if (leaf_indices.empty())
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) leaf_indices.push_back(i);
  std::vector<double> steps(leaf_indices.size(), options.initial_step);
  std::size_t accepted = 0;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    bool active = false;
    for (std::size_t li = 0; li < leaf_indices.size(); ++li) {
      double& step = steps[li];
      if (step < options.min_step) continue;
      if (std::chrono::steady_clock::now() >= options.deadline) return accepted;
      active = true;
      const std::size_t leaf = leaf_indices[li];
      Param params[6];
      const int np = params_of(ev.leaf(leaf).kind, options, params);
      bool improved = false;
      for (int pi = 0; pi < np; ++pi) {
        for (double dir : {1.0, -1.0}) {
          double delta = dir * step;
          bool moved = false;
          // Keep going while it pays, doubling the stride (Figure 4's "small steps towards").
          for (int rep = 0; rep < 6; ++rep) {
            Primitive trial = ev.leaf(leaf);
            move(trial, params[pi], delta);
            const Mismatch m = ev.try_leaf(leaf, trial);
            if (m.total() >= ev.mismatch().total()) break;
            ev.leaf(leaf) = trial;
            ev.update_leaf(leaf);
            ++accepted;
            moved = improved = true;
            delta *= 2;
          }
          if (moved) break;  // no need to try the opposite direction
        }
      }
      if (!improved) step *= 0.5;
    }
    if (!active) break;
  }
  return accepted;
}

}  // namespace csgfit
