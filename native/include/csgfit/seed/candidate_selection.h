// A first tree chosen among primitives read off the input: the program a designer's sketch of
// unions and cuts would be, when the candidates hold its primitives.
#pragma once

#include <optional>
#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree2d.h"

namespace csgfit {

/// The tree (union of some `positives`) minus (union of some `holes`) whose score against
/// `target` (mismatched pixels + k per primitive) is lowest among those greedy addition and
/// then single additions or removals reach, the candidates taken as they are (each rasterised
/// once, so a choice costs a few word operations). Nothing when no positive pays for itself.
std::optional<Node> select_candidates(const Bitmap& target, const std::vector<Primitive>& positives,
                                      const std::vector<Primitive>& holes, double k);

}  // namespace csgfit
