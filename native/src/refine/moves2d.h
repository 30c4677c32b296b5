// Internal to refine/: the parameters of a 2D primitive that the local optimiser moves, and
// how one step moves each.
#pragma once

#include <algorithm>
#include <cmath>

#include "csgfit/model/primitive2d.h"
#include "csgfit/refine/local_opt.h"
#include "refine/moves.h"

namespace csgfit {

struct Moves2D {
  // Left, Right, Bottom, Top: one side of a rectangle moved outwards, the others kept.
  enum class Param { X, Y, W, H, Angle, Apex, Left, Right, Bottom, Top };
  static constexpr int kMaxParams = 7;

  /// Steps are in pixels.
  double unit = 1.0;

  // The parameters worth moving for a primitive (a circle has one size and no orientation).
  static int params_of(const Primitive& p, const LocalOptOptions& o, Param out[kMaxParams]) {
    const PrimitiveKind kind = p.kind;
    int n = 0;
    out[n++] = Param::X;
    out[n++] = Param::Y;
    // A rectangle's sides move one at a time: a plate whose left edge is off by some pixels
    // cannot get there by growing (both sides move) or by shifting (the right side moves too).
    if (kind == PrimitiveKind::Rectangle && o.move_sizes) {
      for (Param side : {Param::Left, Param::Right, Param::Bottom, Param::Top}) out[n++] = side;
      if (o.move_orientation) out[n++] = Param::Angle;
      return n;
    }
    if (o.move_sizes) out[n++] = Param::W;
    if (kind != PrimitiveKind::Circle) {
      if (o.move_sizes) out[n++] = Param::H;
      if (o.move_orientation) out[n++] = Param::Angle;
    }
    if (kind == PrimitiveKind::Triangle && o.move_orientation) out[n++] = Param::Apex;
    return n;
  }

  void move(Primitive& p, Param param, double step) const {
    switch (param) {
      case Param::X:
        p.cx += step;
        break;
      case Param::Y:
        p.cy += step;
        break;
      case Param::W:
        p.w += step;
        if (p.kind == PrimitiveKind::Circle) p.h = p.w;
        break;
      case Param::H:
        p.h += step;
        break;
      case Param::Angle: {
        p.angle += moves::turn_degrees(step, std::max(0.5 * std::max(p.w, p.h), 1.0));
        break;
      }
      case Param::Apex:
        p.apex += step / std::max(0.5 * p.w, 1.0);
        break;
      case Param::Left:
      case Param::Right:
      case Param::Bottom:
      case Param::Top:
        move_side(p, param, step);
        break;
    }
  }

 private:
  // The side moves outwards by `step`, so the centre moves by half of it along the side's normal.
  static void move_side(Primitive& p, Param side, double step) {
    const double a = p.angle * 3.14159265358979323846 / 180, c = std::cos(a), s = std::sin(a);
    const bool along_w = side == Param::Left || side == Param::Right;
    const double sign = (side == Param::Right || side == Param::Top) ? 1 : -1;
    (along_w ? p.w : p.h) += step;
    const double nx = along_w ? c : -s, ny = along_w ? s : c;
    p.cx += sign * nx * step / 2, p.cy += sign * ny * step / 2;
  }
};

}  // namespace csgfit
