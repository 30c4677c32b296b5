// What the two bit-packed grids, Bitmap and VoxelGrid, count alike: both are rows of 64-bit
// words whose padding bits are zero, so whole-word operations and popcounts need no masking.
#pragma once

#include <cstddef>

namespace csgfit {

/// Cells set in a but not in b; set in both; that differ. The grids must have the same
/// dimensions (a VoxelGrid checks: std::invalid_argument).
template <typename Grid>
std::size_t count_and_not(const Grid& a, const Grid& b);
template <typename Grid>
std::size_t count_and(const Grid& a, const Grid& b);
template <typename Grid>
std::size_t count_xor(const Grid& a, const Grid& b);
/// Intersection over union of the set cells; 1 when both are empty.
template <typename Grid>
double iou(const Grid& a, const Grid& b);

}  // namespace csgfit
