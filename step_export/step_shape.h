// The OpenCASCADE solids behind the STEP writer, for code that links OCCT itself (the tests).
#pragma once

#include <TopoDS_Shape.hxx>

#include "csgfit/model/frame.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// The exact solid of one 3D primitive in model coordinates (local frame of primitive3d.h,
/// then rotated and moved to the centre). Throws InputError on non-finite or non-positive sizes.
TopoDS_Shape make_shape(const Primitive3D& p);

/// The tree's solid: primitives combined by BRepAlgoAPI fuse / cut / common. Checked with
/// BRepCheck_Analyzer; throws InputError if the result is empty or invalid.
TopoDS_Shape make_shape(const Node3D& tree);

/// The 2D tree extruded to frame.thickness (see write_step); throws InputError when the
/// thickness is 0, as for an empty or invalid result.
TopoDS_Shape make_shape(const Node& tree, const ModelFrame& frame);

/// Exact volume of a shape (BRepGProp::VolumeProperties).
double shape_volume(const TopoDS_Shape& shape);

/// Writes a shape as AP214 STEP in mm through a temporary file and a rename, `name` being the
/// STEP product's name; throws InputError.
void write_step_shape(const TopoDS_Shape& shape, const std::string& path, const std::string& name);

}  // namespace csgfit
