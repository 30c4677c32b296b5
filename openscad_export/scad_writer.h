// OpenSCAD (.scad) writer for 2D CSG trees.
#pragma once

#include <string>

#include "csgfit/model/frame.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/search/stats.h"

namespace csgfit {

/// How the radius of a circle (and ellipse) is adjusted for OpenSCAD's $fn-gon.
enum class CircleFit {
  Inscribed,      ///< radius as fitted: the polygon's vertices lie on the circle (OpenSCAD's default)
  Circumscribed,  ///< r / cos(180 / $fn): the polygon's edges touch the circle
  EqualArea,      ///< the polygon has the circle's area
};

struct ScadOptions {
  int fn = 96;  ///< $fn for circles and ellipses, written as a variable the user can change
  /// EqualArea agrees best with the solver's raster at pixel centres (measured on 100 random
  /// circle/ellipse trees, 96 x 80 px: 133 / 58 / 53 differing pixels for Inscribed /
  /// Circumscribed / EqualArea at $fn = 96, 1051 / 534 / 447 at $fn = 32).
  CircleFit circle_fit = CircleFit::EqualArea;
  /// Canvas of the source image in pixels (FitResult::width/height), for the header comment and
  /// the Customizer slider ranges; 0 = unknown.
  int width_px = 0, height_px = 0;
};

/// Writes the tree as OpenSCAD 2021.01 source in model coordinates (pixel_size units, y up):
/// named dimensions at the top with Customizer comments, nested unions flattened, 2D geometry,
/// or linear_extrude when frame.thickness > 0. `stats`, if given, goes into a header comment.
std::string to_scad(const Node& tree, const ModelFrame& frame, const ScadOptions& options = {},
                    const FitStats* stats = nullptr);

/// Writes the morph from `a` (morph = 0) to `b` (morph = 1), two trees of one structure with
/// b's angles ending a's turns, as one OpenSCAD model: a `morph` slider (-1, its default,
/// follows $t so that View > Animate plays it; `openscad -D morph=0.3` renders a frame), each
/// primitive's values at both ends as Customizer parameters (one when they agree), and every
/// dimension mix(at A, at B). Sizes may be 0 (a primitive seen in one shape only).
std::string to_scad_morph(const Node& a, const Node& b, const ModelFrame& frame,
                          const std::string& source_b, const ScadOptions& options = {},
                          const FitStats* stats_a = nullptr);

}  // namespace csgfit
