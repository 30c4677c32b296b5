// Seed 003 (Chirehdast & Papalambros): a deterministic first tree by recursive bounding-box
// difference and moment-based matching of regions to primitives.
#pragma once

#include <optional>

#include "csgfit/model/bitmap.h"
#include "csgfit/features/features2d.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree2d.h"

namespace csgfit {

/// A primitive matched to a region, with how well it fits.
struct RegionMatch {
  Primitive primitive;
  double boundary_deviation = 0;  ///< sum of squared boundary distances / perimeter^2 (seed 003)
  std::size_t mismatch = 0;       ///< pixels where the primitive's raster and the region differ
};

/// Matches a region to the primitive library by its area, centroid and principal moments: each
/// allowed kind gets the dimensions its moment equations give (rectangle, ellipse/circle, and
/// the one-parameter family of triangles with those moments, which contains the isosceles and
/// right-angled ones), refined by a short local search against the region; the candidate with the
/// smallest non-dimensional boundary deviation wins. Returns nothing if no kind is allowed or the
/// region is empty.
std::optional<RegionMatch> match_region(const Bitmap& region, PrimitiveSet allowed);

struct DecomposeOptions {
  PrimitiveSet primitives = PrimitiveSet::all();
  double k = 25;          ///< size weight: a match is kept when it scores better than going deeper
  int max_depth = 24;     ///< recursion bound (each level's boxes are strictly smaller in 2D)
};

/// The seed-003 tree of `target`: union over 4-connected components of
/// region(R) = best of { matched primitive, box(R) - union(region(S) for the complementary
/// sub-regions S of R in its box) }, where "best" is the score excess + uncovered + k x primitives
/// and a sub-region may also be left out when that scores better. Always terminates and returns
/// a valid tree; rectangles must be allowed (they are the boxes). Throws std::invalid_argument if
/// the target is empty.
Node decompose(const Bitmap& target, const DecomposeOptions& options);

}  // namespace csgfit
