// Seed 001's pipeline (Fig. 1): redundancy removal, decomposition by dominant halfspaces, the
// remaining solid by two-level minimisation or the GA, redundancy removal again; the result
// checked against the input on samples of its own and kept only if it is the same solid and
// no larger. Written once for 2D and 3D.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/halfspace.h"

namespace csgfit::opt {

enum class RemainingMethod { Auto, Espresso, QuineMcCluskey, SetCover, Genetic };

/// Parses "auto", "espresso", "qmc", "setcover", "ga"; throws InputError otherwise.
RemainingMethod remaining_method_from_string(const std::string& name);
std::string to_string(RemainingMethod method);

struct OptimizeOptions {
  RemainingMethod method = RemainingMethod::Auto;
  double proximity_weight = 2.0;  ///< the GA's w_p (seed: 2)
  double size_weight = 2.0;       ///< the GA's w_s (seed: 2)
  double geometry_weight = 20.0;  ///< the GA's w_g (seed: 20)
  std::uint64_t seed = 1;
  double time_limit = 10.0;       ///< seconds for the GA and the exact set cover
  bool decompose = true;          ///< Sec. 5.2 on (the seed's pipeline)
  std::size_t finest = 0;         ///< SamplingOptions::finest (0: the default)
};

/// One solution of the GA's Pareto front (size against proximity).
struct ParetoPoint {
  Expr tree;
  std::size_t size = 0;
  double proximity = 0;
};

struct OptimizeReport {
  std::size_t size_before = 0, size_after = 0;          ///< seed 001's size: literals + operations
  std::size_t halfspaces_before = 0, halfspaces_after = 0;
  std::size_t opaque = 0;                               ///< opaque leaves, kept as they are
  double proximity_before = 0, proximity_after = 0;
  std::size_t structural_rewrites = 0, sampled_removals = 0;
  std::size_t dominant_halfspaces = 0, remaining_solids = 0, remaining_improved = 0;
  std::size_t empty_decisions = 0, cache_hits = 0;
  std::size_t check_points = 0, check_mismatches = 0;  ///< the final check on fresh samples
  bool reverted = false;                               ///< the check failed: the input came back
  std::vector<ParetoPoint> pareto;                     ///< the GA's front, when it ran
  std::vector<std::pair<std::string, std::size_t>> stage_sizes;  ///< size after each stage
  double seconds = 0;
};

struct OptimizeResult {
  Expr tree;  ///< no Complement nodes (bounded solids only)
  OptimizeReport report;
};

/// Optimises `tree` over `halfspaces`; opaque leaves (indices into a list of the caller's) are
/// kept. Throws InputError when the tree is empty everywhere or unbounded.
template <std::size_t D>
OptimizeResult optimize_tree(const Expr& tree, const HalfspaceList<D>& halfspaces,
                             const OptimizeOptions& options);

}  // namespace csgfit::opt
