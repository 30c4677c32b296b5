// Seed 000's pruning: primitives that do not pay for their price k are removed.
#pragma once

#include <cstddef>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/refine/local_opt.h"

namespace csgfit {

/// Removes primitives whose removal costs fewer than k mismatched pixels (seed 000's pruning),
/// one at a time, best first, then simplifies the tree. Returns the number removed.
std::size_t prune(Node& tree, const Bitmap& target, double k);

/// Removes primitives whose removal costs fewer than k mismatched voxels, one at a time, best
/// first, then simplifies the tree. Returns the number removed.
std::size_t prune(Node3D& tree, const VoxelGrid& target, double k);

/// The pruning that refits: each primitive is removed in turn, the others optimised with
/// `refit`, and the best such tree replaces `tree` while it scores lower (mismatch + k per
/// primitive); at most `rounds` removals. Seed 000's pruning keeps a sliver beside a plate
/// because the plate, where it is, does not cover the sliver's pixels; moved a little, it does.
/// Returns the number removed; `evaluations` grows by what the refits cost.
std::size_t prune_refitted(Node& tree, const Bitmap& target, double k, const LocalOptOptions& refit,
                           std::size_t& evaluations, int rounds = 3);

}  // namespace csgfit
