// What the boundary of a bitmap says the designer drew: the rectangles and triangles its straight
// edges bound and the discs, ellipses and holes its arcs lie on. The 2D counterpart of the
// surface reading.
#pragma once

#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"

namespace csgfit {

struct BoundaryPrimitives {
  std::vector<Primitive> positives;  ///< rectangles, triangles, discs and ellipses of the shape
  std::vector<Primitive> holes;      ///< those whose edges are concave: to be cut
};

/// The boundary's rectangles (boundary_rectangles), triangles (three boundary_lines), circles
/// (boundary_arcs) and ellipses (boundary_ellipses), of the kinds `allowed` holds (a circle as
/// a round ellipse when only ellipses are).
BoundaryPrimitives boundary_primitives(const Bitmap& target, const PrimitiveSet& allowed);

}  // namespace csgfit
