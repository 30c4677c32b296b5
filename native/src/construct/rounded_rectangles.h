// Internal to construct/: rounded rectangles and slots read off their corner arcs, as halfspaces
// of the construction (a rounded box as long as the part is wide).
#pragma once

#include <vector>

#include "literals.h"

namespace csgfit::construct {

/// One literal per rounded outline whose corner arcs (four quarter arcs of one radius at the
/// corners of a rectangle, or two half arcs facing apart: a slot) the surfaces hold.
std::vector<Literal> rounded_rectangles(const MeshSurfaces& surfaces, const Bounds3& domain);

}  // namespace csgfit::construct
