// Internal to step_export/: the exact solid of each primitive in its local frame, and the
// checks of the numbers the writer turns into geometry (each a one-line InputError).
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pnt.hxx>
#include <string>
#include <vector>

#include "csgfit/model/primitive3d.h"

namespace csgfit::step {

/// Far beyond any part in mm, small enough that OCCT's tolerances (1e-7) still mean something.
inline constexpr double kMaxMagnitude = 1e7;

/// v, unless it is not finite or beyond 1e7 (mm): then an InputError naming `what` of `prim`.
double finite(double v, const char* what, const std::string& prim);
/// finite(v), and > 0.
double positive(double v, const char* what, const std::string& prim);
/// A closed polygon through the points, as a wire and as a planar face.
TopoDS_Wire polygon_wire(const std::vector<gp_Pnt>& pts);
TopoDS_Face polygon_face(const std::vector<gp_Pnt>& pts);
/// The face swept along local z by `height`.
TopoDS_Shape extrude(const TopoDS_Face& f, double height);
/// The primitive's exact solid in its local frame (`what` names it in errors).
TopoDS_Shape local_solid(const Primitive3D& p, const std::string& what);

}  // namespace csgfit::step
