// Seed 002's smallest hidden extents, for what a cut can take away: a primitive that reaches
// behind a seen face's plane into space no view saw (a tunnel's lower half under the plate it
// stands on, a sphere's under the same plate) is cut by that plane when no view sees the
// difference.
#pragma once

#include <atomic>
#include <vector>

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// `graph` with the halfspace cuts of `pool` (SignedPrimitive::halfspace) that trim hidden
/// material, greedily, the largest trim first: each cuts the positive nodes whose hidden part
/// behind its plane it takes without changing what the views see (surface, empty and behind
/// points of `evidence`, within a quarter of the size weight `k`), and is kept when it takes at
/// least a twentieth of the tree's hidden volume. Then each block cut from a ball, cylinder or
/// ellipsoid is mirrored through that node's centre, and the opposite flat is cut too where no
/// view sees the difference (a lock's hidden three flats, from its seen three). Nothing changes
/// when the evidence has no hidden points (a scan without a camera). Deterministic.
PrecedenceGraph trim_hidden(PrecedenceGraph graph, const std::vector<SignedPrimitive>& pool,
                            const RangeEvidence& evidence, double k,
                            const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
