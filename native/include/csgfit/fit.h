// Bitmap -> CSG tree: the whole 2D pipeline (seed-003 first tree, seed-000 search) behind one
// call, used by the CLI and the Python module.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "csgfit/bitmap.h"
#include "csgfit/primitive.h"
#include "csgfit/tree.h"

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

/// Everything a fit takes besides the bitmap.
struct FitOptions {
  double k = -1;                ///< size weight; < 0 means 25 scaled to the image area
  PrimitiveSet primitives = PrimitiveSet::all();
  double time_limit = 10;       ///< seconds of wall time for the search
  int threads = 0;              ///< 0 = all cores
  std::uint64_t seed = 1;
  int alternatives = 0;         ///< extra structurally different good trees to return
  SearchParams search;
};

/// k for an image: 25 at 128 x 128, proportional to the pixel count.
double default_k(int width, int height);

/// Progress reported during a fit; the callback returns false to cancel.
struct FitProgress {
  double fraction = 0;          ///< 0..1 of the time budget or convergence, whichever is ahead
  double best_score = 0;
  std::size_t best_primitives = 0;
  std::size_t evaluations = 0;
  double seconds = 0;
};
using ProgressCallback = std::function<bool(const FitProgress&)>;

struct FitStats {
  double k = 0;
  double score = 0;
  std::size_t excess = 0, uncovered = 0;
  std::size_t primitives = 0;
  double iou = 0;
  std::size_t evaluations = 0;   ///< tree evaluations (full or incremental)
  std::size_t trees = 0;         ///< trees searched (perturbations evaluated)
  double seconds = 0;
  std::string stop_reason;       ///< "converged", "time", "max-trees", "cancelled"
};

/// One result tree with its own mismatch.
struct FitTree {
  Node tree;
  FitStats stats;
};

struct FitResult {
  Node tree;                       ///< the best tree, in pixel units, y up
  FitStats stats;
  std::vector<FitTree> alternatives;  ///< structurally different runners-up, best first
  int width = 0, height = 0;
};

/// Fits a CSG tree to `target` (foreground = shape). Throws std::invalid_argument when the
/// target has no foreground pixel ("no shape found") or the options are invalid. Honours
/// `cancel` (checked often) and the progress callback's return value: a cancelled fit returns
/// the best tree found so far with stop_reason "cancelled".
FitResult fit_bitmap(const Bitmap& target, const FitOptions& options,
                     const ProgressCallback& progress = nullptr,
                     const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
