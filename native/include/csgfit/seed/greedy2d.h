// A second deterministic first tree, beside seed 003's: greedy residual cover.
#pragma once

#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree2d.h"

namespace csgfit {

struct GreedyOptions {
  PrimitiveSet primitives = PrimitiveSet::all();
  double k = 25;
  int max_primitives = 64;
  /// Primitives read off the input (boundary_primitives): each is tried where it holds the
  /// step's distance peak, beside the kinds placed at the peak; `proposals` where the tree
  /// leaves pixels uncovered, `cut_proposals` (holes) where it has excess.
  std::vector<Primitive> proposals;
  std::vector<Primitive> cut_proposals;
};

/// Builds a tree one primitive at a time: each step places every allowed kind at the largest
/// maximum of the distance map of what the tree still gets wrong (uncovered pixels are added
/// by union, excess pixels are cut by difference), optimises it locally, and keeps the one that
/// lowers the score most; it stops when nothing lowers it. Seed 003 expresses a part as a box
/// minus its complement; this expresses it as a union of its convex pieces minus its holes,
/// which is often how the part was drawn. Throws std::invalid_argument for an empty target.
Node greedy_cover(const Bitmap& target, const GreedyOptions& options);

}  // namespace csgfit
