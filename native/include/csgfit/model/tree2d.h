// The 2D CSG tree: rectangles, circles, ellipses and triangles under union, difference and
// intersection (the tree itself is written once, in tree.h).
#pragma once

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree.h"

namespace csgfit {

using Node = CsgNode<Primitive>;

/// Renders the tree by scan-converting every primitive and combining (the reference evaluator:
/// simple and slow; the search uses TreeEvaluator).
Bitmap render(const Node& root, int width, int height);

}  // namespace csgfit
