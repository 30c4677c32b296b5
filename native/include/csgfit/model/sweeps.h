// Subtrees of a 3D tree that are a 2D profile swept along an axis or about one: a plate with
// holes is a square minus circles extruded, a turned bush the revolution of its half section.
// The writers draw such a subtree as its designer would (OpenSCAD's linear_extrude and
// rotate_extrude, FreeCAD's Part::Extrusion and Part::Revolution); the tree is the same.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/tree3d.h"

namespace csgfit {

enum class SweepKind { Linear, Revolution };

/// One leaf of a sweep, drawn in the sweep's plane: for a linear sweep the frame's local xy
/// plane, for a revolution the half plane whose x >= 0 is the distance from the axis and whose
/// y is the height along it (the profile OpenSCAD's rotate_extrude takes).
///
/// Linear, the leaf's cross-section:
///  - Box: the rectangle of sides dims[across[0]] and dims[across[1]] centred on (x, y), its
///    first side (along the box's local axis across[0], of its two the one nearer the plane's
///    x axis) turned by `angle` from the plane's x axis, in (-90, 90].
///  - RoundedBox: as a Box's, across its local x and y (across is {0, 1} or {1, 0}), each
///    corner rounded with radius `corner` (OpenSCAD's offset(r = corner) square()).
///  - Cylinder: the circle of radius dims[0] centred on (x, y); a polygonal one's regular
///    polygon has its vertex 0 at `angle`.
///  - TriangularPrism: its triangle (w, h, apex, as the 2D Triangle) centred on (x, y), turned
///    by `angle`, and reflected across its own x axis first when `flipped` (its local z points
///    down the sweep's axis, so the plane sees it from behind).
/// Revolution (x = 0, y the leaf's centre along the axis):
///  - Cylinder: the band [0, r] x [y - h/2, y + h/2].
///  - Cone: the quadrilateral (0, y - h/2), (r1, y - h/2), (r2, y + h/2), (0, y + h/2), with
///    r1 and r2 swapped when `flipped` (its local z points down the axis).
///  - Torus: the circle of radius r centred on (R, y).
///  - Sphere: the half x >= 0 of the circle of radius r centred on (0, y).
struct SweepSection {
  const Primitive3D* leaf = nullptr;
  std::size_t leaf_index = 0;  ///< its index in leaves(tree), pre-order
  double x = 0, y = 0;
  double angle = 0;  ///< degrees, counter-clockwise in the plane
  int across[2] = {0, 1};
  bool flipped = false;
};

/// A subtree that is a sweep, and its frame: model = origin + rotation * local, the axis along
/// local z. A linear sweep fills local z in [0, height]; a revolution turns its profile, drawn
/// in the local xz plane (x >= 0), about local z.
struct Sweep {
  SweepKind kind = SweepKind::Linear;
  const Node3D* root = nullptr;
  std::size_t node = 0;  ///< root's pre-order index in the tree (as for_each_node counts)
  Vec3 origin{0, 0, 0};
  Quaternion rotation;
  double height = 0;                   ///< Linear only
  std::vector<SweepSection> sections;  ///< one per leaf of root, in pre-order

  /// The section of `leaf` (a leaf of root, by address), or nullptr.
  const SweepSection* section_of(const Primitive3D* leaf) const;
};

/// The subtrees of `tree` with at least two leaves that are sweeps, in pre-order. A subtree
/// that is a sweep as a whole is reported once (as a linear sweep when it could be either),
/// and nothing inside it. Lengths agree within 1e-6 of the tree's size, directions within
/// 1e-6 radians.
///  - Linear: every leaf is a prism along one direction (a box along any of its local axes, a
///    round or polygonal cylinder, a triangular prism or a rounded box along its local z), and
///    every leaf spans the subtree's extent along it, found as union = hull, intersection =
///    overlap, difference = the first child's. So a subtracted or intersected leaf may reach
///    beyond the others, as a through-hole does: only its part inside the extent counts. Among
///    several such directions (a tree of boxes), the one of the smallest height.
///  - Revolution: every leaf is round about one line: round cylinders, cones and tori on it,
///    spheres centred on it, at least one leaf not a sphere.
std::vector<Sweep> find_sweeps(const Node3D& tree);

}  // namespace csgfit
