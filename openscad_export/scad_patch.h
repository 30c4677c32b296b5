// The NURBS terminal in OpenSCAD, which has no free-form surfaces: a closed polyhedron whose
// top is the patch sampled on a grid fine enough for a tolerance, its deviation measured.
#pragma once

#include <string>

#include "csgfit/model/bspline_surface.h"

namespace csgfit::scad {

/// The polyhedron of the solid 0 <= z <= S(x, y) over the patch's rectangle (local
/// coordinates), and how far its top strays from the patch.
struct PatchPolyhedron {
  std::string code;        ///< "polyhedron(points = [...], faces = [...]);"
  int cells_x = 0, cells_y = 0;
  double deviation = 0;    ///< largest |S - top| at cell and edge midpoints, model units
};

/// Refines the grid (up to 256 x 256 cells) until the top deviates from the patch by at most
/// `tolerance`; heights below the floor are lifted to a hair above it (a solid of zero
/// thickness is not one OpenSCAD accepts), which counts in the deviation.
PatchPolyhedron patch_polyhedron(const BSplineSurface& patch, double tolerance, int decimals);

}  // namespace csgfit::scad
