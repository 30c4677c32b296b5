// OpenSCAD (.scad) writer for 3D CSG trees.
#pragma once

#include <string>

#include "csgfit/model/tree3d.h"
#include "scad_writer.h"

namespace csgfit {

struct ScadOptions3D {
  int fn = 64;  ///< $fn for spheres, cylinders, cones, ellipsoids and tori, as a variable
  /// How radii are adjusted for OpenSCAD's $fn-gons (as CircleFit does in 2D). EqualArea: each
  /// circle's polygon gets the circle's area, a sphere's ring polyhedron the sphere's volume,
  /// a torus's revolved polygon the torus's volume.
  CircleFit circle_fit = CircleFit::EqualArea;
  std::string source;   ///< input file name: the header comment and the module's name
  std::string summary;  ///< optional one-line fit summary for the header (e.g. "IoU 0.98")
};

/// Writes the tree as OpenSCAD 2021.01 source in model coordinates (the mesh's units, z up):
/// named dimensions at the top with Customizer comments (one tab per primitive), a `segments`
/// variable for $fn, nested unions flattened, the geometry in one named module. Primitives:
/// cube(center = true), sphere, cylinder(h, r1, r2, center = true), scale() sphere for
/// ellipsoids, rotate_extrude of a circle for tori, linear_extrude of a polygon for prisms,
/// linear_extrude() offset(r = corner) square() for rounded boxes, each placed by translate()
/// rotate([a, b, c]). Throws InputError on a tree it cannot write
/// (no primitives, non-finite or non-positive values, $fn out of range).
std::string to_scad(const Node3D& tree, const ScadOptions3D& options = {});

/// Writes the morph from `a` (morph = 0) to `b` (morph = 1), two trees of one structure, as
/// to_scad_morph does in 2D: centres and sizes mix(at A, at B), each primitive turned by
/// rotate(a = mix(0, angle), v = axis) on top of its rotation at A (the short arc to B's).
std::string to_scad_morph(const Node3D& a, const Node3D& b, const std::string& source_b,
                          const ScadOptions3D& options = {});

}  // namespace csgfit
