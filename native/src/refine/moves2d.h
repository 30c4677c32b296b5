// Internal to refine/: the parameters of a 2D primitive that the local optimiser moves, and
// how one step moves each.
#pragma once

#include <algorithm>

#include "csgfit/model/primitive2d.h"
#include "csgfit/refine/local_opt.h"
#include "refine/moves.h"

namespace csgfit {

struct Moves2D {
  enum class Param { X, Y, W, H, Angle, Apex };
  static constexpr int kMaxParams = 6;

  /// Steps are in pixels.
  double unit = 1.0;

  // The parameters worth moving for a kind (a circle has one size and no orientation).
  static int params_of(PrimitiveKind kind, const LocalOptOptions& o, Param out[kMaxParams]) {
    int n = 0;
    out[n++] = Param::X;
    out[n++] = Param::Y;
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
    }
  }
};

}  // namespace csgfit
