// Seed 002's recognition as generate and test: the precedence graph read off the patches is a
// first guess; the search tries every candidate primitive (surface_proposals) in each role the
// graph allows it (a subobject of its own, united before a subobject's cuts or appended after
// them, a cut of one subobject or of all), replaces and removes nodes, and keeps a change when
// the views agree better with the tree than the primitive costs.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <vector>

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

struct GraphSearchOptions {
  double k = 0;  ///< size weight, in evidence_mismatch's units (evidence_k)
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  const std::atomic<bool>* cancel = nullptr;
  /// Changes polished (their new primitive by the pattern search) per step: the best this many
  /// by their unpolished score.
  int polished_per_step = 3;
};

struct GraphSearchStats {
  std::size_t trials = 0;     ///< graphs scored
  std::size_t accepted = 0;   ///< changes kept
  double score_before = 0, score_after = 0;  ///< mismatch + k x primitives
};

/// Improves `graph` against `evidence` by best-improvement steps over `pool` until no change
/// pays, the deadline passes or `cancel` turns true. Deterministic.
PrecedenceGraph search_graph(PrecedenceGraph graph, const std::vector<SignedPrimitive>& pool,
                             const RangeEvidence& evidence, const GraphSearchOptions& options,
                             GraphSearchStats* stats = nullptr);

}  // namespace csgfit
