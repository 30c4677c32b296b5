// Dimensions a tree holds more than once: the equal radii of a row of holes, the common centre
// of concentric circles, the one height of holes drilled through a plate. The writers name each
// once (a Customizer parameter in the .scad, a spreadsheet cell in FreeCAD), so that editing it
// changes every primitive that uses it.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// Which number of a primitive a shared dimension stands for, in the primitive's own units: a
/// circle's radius is half its `w`; in 3D, a sphere's or cylinder's radius is dims[0] and a
/// cylinder's length along its axis (Length) dims[2].
enum class DimensionField { CentreX, CentreY, Width, Height, Radius, Length };

/// The JSON / .scad name of a field: "cx", "cy", "w", "h", "r", "h" (a cylinder's height).
std::string_view field_name(DimensionField field);

/// One field of one primitive; `leaf` indexes leaves(tree) (pre-order).
struct DimensionUse {
  std::size_t leaf;
  DimensionField field;
  bool operator==(const DimensionUse& o) const { return leaf == o.leaf && field == o.field; }
  bool operator<(const DimensionUse& o) const {
    return leaf != o.leaf ? leaf < o.leaf : field < o.field;
  }
};

/// One value used by several primitives (or twice by one: a square's sides).
struct SharedDimension {
  std::string name;  ///< e.g. "hole_r", "centre_x", "rect_side2": an identifier for .scad and FreeCAD
  std::vector<DimensionUse> uses;
};

/// The tree's shared dimensions: radii of circles that are exactly equal, sides of rectangles
/// (widths and heights together: a bar's width is the same dimension whichever way it is turned)
/// that are exactly equal, and the centre of circles and ellipses that share it exactly. Equality is exact on purpose: the snapping (snap2d.h) makes design-equal
/// values identical, and a value a user edits apart stops being shared.
std::vector<SharedDimension> shared_dimensions(const Node& tree);

/// The 3D tree's shared dimensions: radii of spheres and cylinders that are exactly equal
/// (snap3d makes near-equal ones so), and heights of cylinders that are exactly equal.
std::vector<SharedDimension> shared_dimensions(const Node3D& tree);
/// The same among the uses that `drawn` accepts only: a writer names what it draws (a
/// cylinder's height does not appear in a linear sweep's profile), and a value left with one
/// use is not shared.
std::vector<SharedDimension> shared_dimensions(
    const Node3D& tree, const std::function<bool(const DimensionUse&)>& drawn);

/// Whether the leaf (pre-order index) is subtracted: under the cut-away side of an odd number of
/// differences. A hole.
template <typename P>
std::vector<bool> subtracted_leaves(const CsgNode<P>& tree);

/// The value of `field` on p, in its own units (a circle's Radius is w / 2).
double field_value(const Primitive& p, DimensionField field);
double field_value(const Primitive3D& p, DimensionField field);

}  // namespace csgfit
