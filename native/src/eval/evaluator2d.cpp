// The 2D tape: regions are ranges of image rows.
#include "csgfit/eval/evaluator2d.h"

#include <algorithm>

#include "eval/evaluator_impl.h"

namespace csgfit {

template class EvaluationTape<BitmapTape>;

BitmapTape::Region BitmapTape::region_of(const Primitive& p, const Bitmap& target) {
  Region r;
  row_range(p, target.height(), r.begin, r.end);
  return r;
}

BitmapTape::Region BitmapTape::hull(const Region& a, const Region& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return Region{std::min(a.begin, b.begin), std::max(a.end, b.end)};
}

void BitmapTape::rasterize_into(const Primitive& p, Bitmap& grid) { csgfit::rasterize_into(p, grid); }

}  // namespace csgfit
