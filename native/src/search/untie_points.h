// The last touch on a fit to points: every face and size the points do not pin down is put
// where a sampled grid says its edge is, not at its last row of points.
#pragma once

#include <chrono>

#include "csgfit/model/tree3d.h"
#include "csgfit/search/point_fitness.h"

namespace csgfit {

/// For each analytic leaf, in turn: each box face (and prism side) moved alone, each other
/// kind's centre coordinate and free size, over the range within three point spacings where the
/// fitness stays what it is (to 1e-12). A scan from above sees a face's last row of points, not
/// the edge past it, and the fit leaves the edge at that row; the parameter is moved half a
/// spacing from the range's nearer end towards the other (at most to the middle), as a grid's
/// sample stands for the cell around it. Where the points pin a parameter (a wall seen all
/// around) the range is empty and nothing moves. Stops at `deadline`; `terms` is updated.
void untie_against_points(Node3D& tree, FitnessTerms& terms, const PointTarget& target,
                          const FitnessWeights& weights, std::chrono::steady_clock::time_point deadline);

}  // namespace csgfit
