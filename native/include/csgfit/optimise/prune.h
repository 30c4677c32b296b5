// Seed 000's pruning: primitives that do not pay for their price k are removed.
#pragma once

#include <cstddef>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// Removes primitives whose removal costs fewer than k mismatched pixels (seed 000's pruning),
/// one at a time, best first, then simplifies the tree. Returns the number removed.
std::size_t prune(Node& tree, const Bitmap& target, double k);

/// Removes primitives whose removal costs fewer than k mismatched voxels, one at a time, best
/// first, then simplifies the tree. Returns the number removed.
std::size_t prune(Node3D& tree, const VoxelGrid& target, double k);

}  // namespace csgfit
