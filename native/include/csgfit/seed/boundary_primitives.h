// What the boundary of a bitmap says the designer drew: the rectangles its straight walls bound
// and the discs and holes its circular arcs lie on. The 2D counterpart of the surface reading.
#pragma once

#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"

namespace csgfit {

struct BoundaryPrimitives {
  std::vector<Primitive> positives;  ///< rectangles and discs of the shape
  std::vector<Primitive> holes;      ///< circles whose arcs are concave: to be cut
};

/// The boundary's rectangles (boundary_rectangles) and circles (boundary_arcs), of the kinds
/// `allowed` holds (a circle as a round ellipse when only ellipses are).
BoundaryPrimitives boundary_primitives(const Bitmap& target, const PrimitiveSet& allowed);

}  // namespace csgfit
