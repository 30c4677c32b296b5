// The "sweeps" block of a 3D document (docs/JSON_SCHEMA.md): the subtrees find_sweeps finds,
// for readers that draw them as extrusions and revolutions of a profile (the FreeCAD builder).
#pragma once

#include "csgfit/model/tree3d.h"
#include "io/json/json_fields.h"

namespace csgfit::json_detail {

/// Each sweep of the tree: its node, kind, frame, height and every leaf's section as a 2D
/// shape in the sweep's plane; an empty array when the tree has none. Written from the tree,
/// never read back (the tree is the truth).
ojson sweeps_to_json(const Node3D& tree);

}  // namespace csgfit::json_detail
