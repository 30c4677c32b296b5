// Design values for 2D trees: round numbers where they cost (almost) nothing, and boundaries
// kept off pixel centres so that every renderer agrees with the solver's raster.
#pragma once

#include <cstddef>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/model/primitive2d.h"

namespace csgfit {

/// What snap_to_design_values changed.
struct DesignSnaps {
  std::size_t snapped = 0;          ///< parameters given a design value
  double straightening_cost = 0;    ///< pixels the near-right angles added beyond the budget
};

/// Rounds parameters to values a designer would type, where that costs (almost) nothing:
/// ellipses with nearly equal axes become circles (if allowed), angles go to multiples of 15
/// degrees, else whole degrees, near-equal radii and sides one value. Each change is kept only if
/// the mismatch grows by no more than what is left of `pixel_budget` (spent as it goes), except
/// that an angle within 0.5 degrees of a multiple of 15 always snaps (its cost is reported).
/// Last, positions and sizes go to half pixels wherever that changes no pixel.
DesignSnaps snap_to_design_values(TreeEvaluator& evaluator, PrimitiveSet allowed,
                                  double pixel_budget);

/// Moves primitive boundaries off pixel centres by a few thousandths of a pixel without changing
/// any pixel, so that any renderer (OpenSCAD's polygons, FreeCAD's solids) agrees with the
/// solver's raster, whose inside test includes the boundary. Returns the number moved.
std::size_t untie(TreeEvaluator& evaluator);

}  // namespace csgfit
