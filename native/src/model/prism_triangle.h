// Internal to model/: the triangle of a prism in its local xy.
#pragma once

#include "csgfit/model/primitive3d.h"

namespace csgfit {

// Triangle vertices of a prism (or the 2D Triangle) in its local xy, counter-clockwise.
inline void triangle_local(const Primitive3D& p, double t[3][2]) {
  const double w = p.dims[0], h = p.dims[1];
  t[0][0] = -w / 2, t[0][1] = -h / 2;
  t[1][0] = w / 2, t[1][1] = -h / 2;
  t[2][0] = p.apex * w / 2, t[2][1] = h / 2;
}

}  // namespace csgfit
