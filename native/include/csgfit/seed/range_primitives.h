// Seed 002's primitive recognition (Sec. 3): each quadric patch becomes a sphere, cylinder, cone
// or torus with its sign from the patch's convexity and its altitude from its points; planes
// that are bases of those are absorbed; the other planes form blocks from perpendicular
// neighbours, positive at a convex corner and negative at a concave one.
#pragma once

#include <vector>

#include "csgfit/features/surface_detect.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// The primitives of a segmented scan and what the precedence graph needs of them.
struct RecognisedPrimitives {
  std::vector<SignedPrimitive> primitives;
  std::vector<std::vector<int>> adjacent;      ///< per primitive: the primitives it touches
  std::vector<std::vector<Vec3>> patch_points; ///< per primitive: its patches' points
};

/// Which patches touch: pairs with at least a few points closer than `radius`.
std::vector<std::vector<int>> patch_adjacency(const std::vector<SurfacePatch>& patches,
                                              const std::vector<Vec3>& points, double radius);

/// Recognises the primitives of `patches` (over `points`; each patch's sign is its `convex`).
/// `diagonal` is the part's size, for the tolerances; `contact` the distance at which two
/// patches touch (a few point spacings).
RecognisedPrimitives recognise_primitives(const std::vector<SurfacePatch>& patches,
                                          const std::vector<Vec3>& points, double diagonal,
                                          double contact);

}  // namespace csgfit
