// Primitives read off a part's surface: seed 002's recognition and precedence graph on any
// oriented surface points (a range image's, a mesh's samples). For range images they are the
// result; for meshes (issue 11) a first tree and the proposals of the 3D search.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "csgfit/features/surface_detect.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/seed/precedence_graph.h"
#include "csgfit/seed/range_primitives.h"

namespace csgfit {

/// The median distance from a point to its nearest neighbour, over an even sample of 400.
double point_spacing(const std::vector<Vec3>& points);

/// `base` with the quadric kinds that `kinds` does not allow switched off; planes stay, since
/// they are the bases of cylinders and cones too.
SurfaceDetectOptions detector_for(SurfaceDetectOptions base, const PrimitiveSet3D& kinds);

/// What a surface says: its patches and the precedence graph of their primitives.
struct SurfaceReading {
  std::vector<SurfacePatch> patches;
  PrecedenceGraph graph;
  /// Every primitive recognised, before the graph drops the cuts that cut nothing.
  std::vector<SignedPrimitive> recognised;
  double diagonal = 0;  ///< part_diagonal of the points
  double contact = 0;   ///< how close two patches' points come where the patches touch
};

/// Detects the patches of `points` (unit `normals` out of the part), recognises their
/// primitives (blocks only where boxes are allowed, each kind only where `kinds` allows it)
/// and orders them in the precedence graph. Deterministic for a given seed.
SurfaceReading read_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                            const SurfaceDetectOptions& detect, const PrimitiveSet3D& kinds,
                            std::uint64_t seed, const std::atomic<bool>* cancel = nullptr);

/// What the graph search may try beyond the reading's own graph (seed 002's candidates, each in
/// every role it could play): every recognised primitive with its sign; for each plane patch
/// the slab as deep as the part reaches behind it and the halfspace cuts on either side (a face
/// a cut left; or a hidden part trimmed away, as a half cylinder's lower half); and the block of
/// each convex corner of two or three faces alone (where the reading joined the faces of
/// neighbouring blocks into one). Each cut reaches through the points' box. Near-duplicates are
/// kept once. Blocks and cuts only where `kinds` has boxes.
std::vector<SignedPrimitive> surface_proposals(const SurfaceReading& reading,
                                               const std::vector<Vec3>& points,
                                               const PrimitiveSet3D& kinds);

/// Whether two signed primitives are one: same kind, sides and sign, centre, sizes and axes
/// (all three: a polygon's turn about its axis counts) within `near`.
bool alike(const SignedPrimitive& a, const SignedPrimitive& b, double near);

/// Adds to `pool` the primitives of `more` that are not already in it (alike within 1 % of
/// `diagonal`).
void add_distinct(std::vector<SignedPrimitive>& pool, const std::vector<SignedPrimitive>& more,
                  double diagonal);

/// Flips the normals that point into `solid` (a mesh wound inside out in places): each is
/// judged by the voxels 1.5 voxels either side of its point.
void orient_outwards(std::vector<Vec3>& normals, const std::vector<Vec3>& points,
                     const VoxelGrid& solid);

}  // namespace csgfit
