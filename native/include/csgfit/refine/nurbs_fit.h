// The NURBS terminal's local optimiser (seed 004, issue 14): its control net fitted by least
// squares to the points under it (model/bspline_surface's fit_heights), the net's size chosen
// by how well it predicts points it was not fitted to.
#pragma once

#include <vector>

#include "csgfit/model/primitive3d.h"

namespace csgfit {

struct PatchFit {
  Primitive3D terminal;   ///< kind Nurbs, floor centre at (rectangle centre, floor)
  int nu = 0, nv = 0;     ///< the chosen net
  NetSpacing spacing = NetSpacing::Greville;  ///< where its columns and rows stand
  double rms = 0;         ///< residual along z on all points
  double holdout_rms = 0; ///< on the fifth of the points each candidate net was not fitted to
};

/// A bicubic patch over the points' x-y box standing on z = floor: every net of 4..24 control
/// points a direction (at most a third as many vertices as points), on Greville or equally
/// spaced columns, with four bending weights, is fitted to four fifths of the points and judged
/// on the rest; the best (a smaller net when within 2 %) is refitted to
/// all. Throws std::invalid_argument when the points do not span an x-y rectangle or are fewer
/// than 20.
PatchFit fit_height_patch(const std::vector<Vec3>& points, double floor);

}  // namespace csgfit
