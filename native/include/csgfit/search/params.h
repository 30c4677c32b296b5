// The search's parameters: seed 000's Tables 1 and 2, and the named presets.
#pragma once

#include <string>

namespace csgfit {

/// Search parameters (seed 000, Tables 1 and 2). `paper()` returns the paper's values; the
/// default constructor keeps its operators and their probabilities and departs where
/// measurement showed it pays (docs/ALGORITHMS.md): seeded first trees, a small population, a
/// larger tree budget.
struct SearchParams {
  int population = 24;           ///< |S|, candidate-solution set size (over all threads)
  int max_trees = 200000;        ///< N, max. trees searched
  int max_stale = 6000;          ///< B, max. trees searched without improvement
  int refocus_interval = 50;     ///< n, refocus every n trees
  double initial_size_mean = 10; ///< a
  double initial_size_sd = 2;    ///< s
  double added_size_mean = 3;    ///< a'
  double added_size_sd = 1.5;    ///< s'
  int local_iterations = 80;     ///< M, max. iterations of the local optimiser
  double p_rep = 0.3, p_add = 0.3, p_cut = 0.3, p_mod = 0.1;  ///< Table 1
  /// Start from the seed-003 tree and the greedy cover instead of random trees.
  bool seed_with_decomposition = true;

  static SearchParams paper();
  /// Named settings shared by the CLI (--quality, --preset) and the Python module: "fast",
  /// "default", "best", or "paper" (Table 2 as it is). Throws std::invalid_argument otherwise.
  static SearchParams for_quality(const std::string& name);
};

}  // namespace csgfit
