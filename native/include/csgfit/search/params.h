// The search's parameters: seed 000's Tables 1 and 2, the odds of its perturbations, how the
// islands share their trees, and the named presets.
#pragma once

#include <string>

namespace csgfit {

/// How often each perturbation is drawn (relative weights): seed 000's REP, ADD, CUT and MOD
/// (Table 1), and INT, ours, which intersects a subtree with a primitive matched to the whole
/// target (3D). An operator that finds nothing to act on falls back to REP.
struct OperatorOdds {
  double rep = 0.3, add = 0.3, cut = 0.3, mod = 0.1, intersect = 0;
};

/// How the islands of a parallel search share trees, once per generation.
enum class Migration {
  /// Every `migration_interval` generations each island's worst tree is replaced by its
  /// neighbour's best (a ring): the 2D search, whose islands hold populations.
  RingOfBests,
  /// When the best tree improved, it moves to the island that has been stuck longest: the 3D
  /// search, whose islands each climb from one tree.
  BestToStuckest,
};

/// Search parameters (seed 000, Tables 1 and 2). `paper()` returns the paper's values; the
/// default constructor keeps its operators and their probabilities and departs where
/// measurement showed it pays (docs/ALGORITHMS.md): seeded first trees, a small population, a
/// larger tree budget. `for_3d()` is the voxel search's.
struct SearchParams {
  int population = 24;           ///< |S|, candidate-solution set size (over all threads)
  int max_trees = 200000;        ///< N, max. trees searched
  int max_stale = 6000;          ///< B, max. trees searched without improvement
  int refocus_interval = 50;     ///< n, refocus every n trees (0 = never)
  double initial_size_mean = 10; ///< a
  double initial_size_sd = 2;    ///< s
  double added_size_mean = 3;    ///< a'
  double added_size_sd = 1.5;    ///< s'
  int local_iterations = 80;     ///< M, max. iterations of the local optimiser
  OperatorOdds odds;             ///< Table 1
  /// Start from the seed-003 tree and the greedy cover instead of random trees.
  bool seed_with_decomposition = true;
  /// Perturbations per island between two synchronisations of the islands.
  int generation = 50;
  Migration migration = Migration::RingOfBests;
  int migration_interval = 4;    ///< generations between RingOfBests migrations
  /// A child replaces its parent when it scores lower by more than this.
  double accept_margin = 0;
  /// The size weight k of a 128 x 128 image when none is given (default_k scales it to the
  /// pixel count). The paper's Table 2 has 25; at 10 every 2D benchmark category fits closer
  /// than potrace with under half its numbers (docs/ALGORITHMS.md).
  double k_at_128 = 11;

  static SearchParams paper();
  /// The 3D voxel search: one tree per island, 4 perturbations a generation, the best tree to
  /// the stuck island, ADD at the residual most of the time and INT now and then.
  static SearchParams for_3d();
  /// Named settings shared by the CLI (--quality, --preset) and the Python module: "fast",
  /// "default", "best", or "paper" (Table 2 as it is). Throws std::invalid_argument otherwise.
  static SearchParams for_quality(const std::string& name);
  /// The 2D morph's pair search: "default" (our first trees, copied into both trees of a
  /// pair, beside random pairs of a = 5 primitives) or "paper" (Table 2 with a = 5, as the
  /// seed's morphing runs). Throws std::invalid_argument otherwise.
  static SearchParams for_morph(const std::string& preset);
};

}  // namespace csgfit
