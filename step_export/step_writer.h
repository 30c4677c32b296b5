// STEP (ISO 10303, AP214) writer for CSG trees, through OpenCASCADE's exact B-rep booleans.
//
// The solver core knows nothing of OpenCASCADE: this is its own library (csgfit_step), linked
// into the CLI and the tests only. This header is OCCT-free; step_shape.h gives the
// TopoDS_Shape itself to code that links OCCT anyway.
#pragma once

#include <string>

#include "csgfit/model/frame.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

struct StepOptions {
  std::string source;  ///< input file name: the STEP product's name (default "csgfit")
};

/// Writes the tree as one exact solid (AP214, millimetres) to `path`. A 3D tree's coordinates
/// are the mesh's own units and are written as mm (as the .scad writer does). Each primitive
/// becomes the exact OpenCASCADE solid (spheres, cylinders, cones and tori as analytic
/// surfaces, ellipsoids as a scaled sphere), placed by its centre and quaternion, and the
/// operators become BRepAlgoAPI fuse / cut / common. The result must pass BRepCheck_Analyzer;
/// an invalid or empty solid, a bad primitive or an unwritable path is an InputError with a
/// one-line reason, and `path` is then left as it was (the file is written to a temporary
/// name in the same folder and renamed).
void write_step(const Node3D& tree, const std::string& path, const StepOptions& options = {});

/// Writes a 2D tree extruded to frame.thickness (z from 0 to thickness, model = pixel *
/// pixel_size, y up), the solid the 2D .scad writer's linear_extrude describes. A thickness of
/// 0 is an InputError ("STEP needs a thickness"); otherwise as the 3D write_step.
void write_step(const Node& tree, const ModelFrame& frame, const std::string& path,
                const StepOptions& options = {});

/// The exact volume (BRepGProp) of the solid write_step would write, in cubic model units.
/// Throws InputError where write_step would.
double step_volume(const Node3D& tree);
double step_volume(const Node& tree, const ModelFrame& frame);

/// Whether the extension of `path` is .step or .stp (any case).
bool is_step_path(const std::string& path);

}  // namespace csgfit
