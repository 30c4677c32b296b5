// Flat, incremental evaluation of a 2D CSG tree against a target bitmap.
#pragma once

#include <cstddef>

#include "csgfit/eval/evaluator.h"
#include "csgfit/eval/mismatch.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"

namespace csgfit {

/// The 2D part of the tape: a region is a range of image rows [begin, end), one run of words.
struct BitmapTape {
  using Grid = Bitmap;
  using Primitive = csgfit::Primitive;
  struct Region {
    int begin = 0, end = 0;
    bool empty() const { return begin >= end; }
  };

  static Region region_of(const Primitive& p, const Bitmap& target);
  static Region all_rows(const Bitmap& target) { return Region{0, target.height()}; }
  static Region hull(const Region& a, const Region& b);
  template <typename F>
  static void for_each_run(const Region& r, const Bitmap& grid, F&& f) {
    if (r.empty()) return;
    const std::size_t wpr = static_cast<std::size_t>(grid.words_per_row());
    f(static_cast<std::size_t>(r.begin) * wpr, static_cast<std::size_t>(r.end - r.begin) * wpr);
  }
  static void rasterize_into(const Primitive& p, Bitmap& grid);
  static Bitmap blank_like(const Bitmap& target) { return Bitmap(target.width(), target.height()); }
};

/// Evaluates one 2D tree over a canvas; the mismatch counts pixels (see EvaluationTape).
class TreeEvaluator : public EvaluationTape<BitmapTape> {
 public:
  TreeEvaluator(const Bitmap& target, Node& tree) : EvaluationTape(target, tree) {}
};

}  // namespace csgfit
