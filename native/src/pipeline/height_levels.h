// First trees for a part seen from above (seed 004's 2.5D setting): every flat height level's
// footprint, fitted by the bitmap pipeline and extruded from the floor to the level. A part
// made of blocks and holes standing on a table (the seed's crossed bars, a boss on a plate) is
// a union of such extrusions; the GP/ES then only prunes and polishes instead of discovering
// four bars of exact length and angle at once.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/search/point_fitness.h"

namespace csgfit {

struct LevelOptions {
  double floor = 0;          ///< where the extrusions start (the table, or the scan's bottom)
  double seconds = 2;        ///< the bitmap fits' budget, shared by the levels
  /// Boxes, upright cylinders and prisms over rectangles, circles and triangles: whichever of
  /// them the search may use.
  PrimitiveSet3D primitives = PrimitiveSet3D::parse("box,cylinder");
  int threads = 0;
  std::uint64_t seed = 1;
};

/// The level trees of `target` (none when it has no flat level): the union of the extruded
/// footprints and, when a footprint's hole was filled because its bottom is curved (a dimple,
/// not a pocket), the same minus the curved primitives `detected` subtracts.
std::vector<Node3D> level_trees(const PointTarget& target, const std::vector<Node3D>& detected,
                                const LevelOptions& options, const std::atomic<bool>* cancel);

}  // namespace csgfit
