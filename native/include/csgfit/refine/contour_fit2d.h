// Least-squares refinement of a 2D tree's primitives against the bitmap's sub-pixel contour:
// the 2D counterpart of refine_to_surface.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/features/boundary_curves.h"
#include "csgfit/refine/boundary_fit.h"

namespace csgfit {

/// Fits every leaf to the contour points its boundary passes nearest (within `inlier` pixels,
/// where its edge runs the way the contour does: corners, which the contour rounds off, are
/// left out), so that a primitive's edges sit where the bitmap's sub-pixel edge does and not
/// merely anywhere that leaves the same pixels. A refined primitive replaces the old one only
/// when the tree then mismatches no more pixels. Returns the number of primitives changed.
std::size_t refine_to_contour(TreeEvaluator& evaluator, const std::vector<ContourPoint>& contour,
                              const BoundaryFitOptions& options = {});

}  // namespace csgfit
