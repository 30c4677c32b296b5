// Internal: OpenSCAD's primitives as halfspaces: an inside test in the call's own frame and
// bounds, put in the world by the call's matrix.
#pragma once

#include <memory>
#include <optional>

#include "csgfit/io/openscad_program.h"

namespace csgfit::scad_shapes {

/// A 2D solid given by a boolean tree over 2D halfspaces (the children of an extrusion).
struct Solid2D {
  opt::Expr tree;
  opt::HalfspaceList<2> halfspaces;
  bool contains(const opt::Point<2>& p) const;
  opt::Box<2> bounds() const;
};

/// The 3D halfspace of cube, sphere or cylinder under `world`; nullopt for other names.
/// Throws InputError (naming `where`) for missing or bad sizes.
std::optional<opt::Halfspace<3>> primitive3(const ScadCall& call, const Matrix4& world, const std::string& where);
/// The 2D halfspace of circle, square or polygon under `world` (its xy part).
std::optional<opt::Halfspace<2>> primitive2(const ScadCall& call, const Matrix4& world, const std::string& where);
/// linear_extrude or rotate_extrude of `section` under `world`.
opt::Halfspace<3> extrusion(const ScadCall& call, std::shared_ptr<const Solid2D> section, const Matrix4& world,
                            const std::string& where);

bool is_extrusion(const std::string& name);
bool is_2d_primitive(const std::string& name);
bool is_3d_primitive(const std::string& name);

}  // namespace csgfit::scad_shapes
