// The NURBS terminal's JSON fields (docs/JSON_SCHEMA.md "nurbs"): degree, counts, knots and the
// control net in the leaf's local frame, written and read by json3d.cpp.
#pragma once

#include <string>

#include "csgfit/model/primitive3d.h"
#include "io/json/json_fields.h"

namespace csgfit::json_detail {

/// Adds size, degree, counts, knots_u, knots_v and control_points to the leaf j.
void write_nurbs_fields(const Primitive3D& p, const std::string& where, ojson& j);
/// Reads them into p (kind Nurbs); fails on knots that are not clamped, a net of the wrong
/// size, control points off the rectangle's Greville grid or not finite.
void read_nurbs_fields(const ojson& j, const std::string& where, Primitive3D& p);

}  // namespace csgfit::json_detail
