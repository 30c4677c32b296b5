// Bitmap -> CSG tree: the whole 2D pipeline (seed-003 first tree, seed-000 search) behind one
// call, used by the CLI and the Python module.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/search/params.h"
#include "csgfit/search/stats.h"

namespace csgfit {

/// Everything a fit takes besides the bitmap.
struct FitOptions {
  double k = -1;                ///< size weight; < 0 means 25 scaled to the image area
  PrimitiveSet primitives = PrimitiveSet::all();
  double time_limit = 10;       ///< seconds of wall time for the search
  int threads = 0;              ///< 0 = all cores
  std::uint64_t seed = 1;
  int alternatives = 0;         ///< extra structurally different good trees to return
  SearchParams search;
  bool optimize_tree = true;    ///< seed 001's optimiser as the last stage (same solid, smaller tree)
};

/// k for an image: k_at_128 at 128 x 128 (SearchParams::k_at_128), proportional to the pixel count.
double default_k(int width, int height, double k_at_128 = SearchParams{}.k_at_128);

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
