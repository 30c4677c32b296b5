// Cuts proposed by what the views saw empty inside a tree: seed 000's ADD at the residual, for
// range evidence. A notch whose faces no view sees (a corner cut away on the hidden side) shows
// only as rays that pass through where the tree has material.
#pragma once

#include <vector>

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// For each positive node of `graph` and each cluster of the empty evidence points that lie
/// deeper than half a tolerance inside both the tree and that node: a box in the node's own
/// frame around the cluster, reaching out through the node's faces it comes near, as a
/// conjectured negative primitive; and where a plane takes the cluster without the seen
/// material beside it (a bevel, a slanted face no view sees), the cut beyond that plane. The
/// plane's normal is tried along the node's faces, edges and corners and 98 spread directions;
/// of the planes that take nearly the most, the one giving up least hidden volume wins.
/// Clusters are joined at `gap` (model units); those of fewer than `min_points` are ignored.
std::vector<SignedPrimitive> pocket_proposals(const PrecedenceGraph& graph,
                                              const RangeEvidence& evidence, double gap,
                                              std::size_t min_points = 20);

}  // namespace csgfit
