// An OpenSCAD program (its flattened .csg) as the optimiser sees it: the boolean tree over
// halfspaces, each primitive kept with its world matrix and its own call text, so that what we
// write back is OpenSCAD's own primitive under the same placement. Calls we cannot sample
// (hull, minkowski, polyhedron, text, import, surface, ...) are opaque leaves, kept verbatim.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "csgfit/io/openscad_csg.h"
#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/halfspace.h"

namespace csgfit {

/// Row-major 4 x 4 affine matrix, as in OpenSCAD's multmatrix.
using Matrix4 = std::array<double, 16>;

/// A leaf: its call (OpenSCAD text, children included) under its world matrix.
struct ScadLeaf {
  Matrix4 matrix{};
  std::string call;
  std::size_t line = 0;
};

struct ScadProgram {
  int dimension = 3;  ///< 2 when the top-level solid is 2D (circle, square, polygon)
  opt::Expr tree;
  std::vector<ScadLeaf> leaves;   ///< by halfspace index
  std::vector<ScadLeaf> opaque;   ///< by opaque index
  opt::HalfspaceList<3> halfspaces3;
  opt::HalfspaceList<2> halfspaces2;
  std::size_t operations = 0;     ///< boolean operations read (union, difference, intersection)
};

/// The program of a parsed .csg (`text` is what was parsed, for the leaves' call text).
/// Throws InputError for a singular or non-finite matrix, a 2D and 3D mix at one level, an
/// empty program.
ScadProgram program_from_csg(const std::vector<ScadCall>& calls, std::string_view text,
                             const std::string& file_name);

/// Reads a .scad (through OpenSCAD) or a .csg file into its program.
ScadProgram read_openscad_program(const std::string& path);

struct ScadWriteOptions {
  bool csg_style = false;  ///< true: multmatrix everywhere (a .csg); false: translate/rotate
  std::string header;      ///< comment lines put first (each without "//")
  /// A complement ~X (only an inflated tree has one) is written as `U - X`, U a box around
  /// the whole program this many times its size (and one unit more).
  double universe_scale = 1.2;
};

/// The program with `tree` (over its leaves, no Complement) as OpenSCAD text.
std::string write_openscad_program(const ScadProgram& program, const opt::Expr& tree,
                                   const ScadWriteOptions& options);

}  // namespace csgfit

#include "csgfit/model/tree3d.h"

namespace csgfit {

/// The program as one of our 3D trees (for .json, STEP and FreeCAD): cube, sphere and
/// cylinder leaves under a rotation, a translation and a scale (a scaled sphere is an
/// ellipsoid). Throws InputError naming the first leaf that has no such form (an opaque or
/// extruded leaf, a sheared or mirrored placement) and the formats that keep it.
Node3D node3d_of(const ScadProgram& program, const opt::Expr& tree);

}  // namespace csgfit
