// The whole tree against what the views saw (seed 002's step 5, beyond the seed): surface
// points should lie on the tree's surface and empty points outside it. Used to drop primitives
// the evidence does not need and to polish the rest by seed 000's pattern search.
#pragma once

#include <atomic>
#include <chrono>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/features/range_evidence.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// The tree's mismatch with the evidence, in sixty-fourths of a sample: uncovered = surface
/// points off the tree's surface (graded up to one tolerance), excess = empty points inside it
/// (graded up to one tolerance deep).
Mismatch evidence_mismatch(const Node3D& tree, const RangeEvidence& evidence);

/// The size weight for the evidence: what a primitive must explain to be kept, 0.2 % of the
/// samples, in evidence_mismatch's units.
double evidence_k(const RangeEvidence& evidence);

/// Pattern search on every leaf's parameters against the evidence until `deadline` (or
/// `cancel`). Returns the accepted moves.
std::size_t refine_to_evidence(Node3D& tree, const RangeEvidence& evidence,
                               std::chrono::steady_clock::time_point deadline,
                               const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
