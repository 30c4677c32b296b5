#include "csgfit/search/stats.h"

namespace csgfit {

void set_mismatch_stats(FitStats& s, const Mismatch& m, std::size_t target_voxels,
                        std::size_t primitives, double k) {
  s.k = k;
  s.excess = m.excess + m.outside;
  s.uncovered = m.uncovered;
  s.primitives = primitives;
  s.score = score(m, primitives, k);
  const double tc = static_cast<double>(target_voxels);
  const double uni = tc + static_cast<double>(s.excess);
  s.iou = uni > 0 ? (tc - static_cast<double>(s.uncovered)) / uni : 1.0;
}

}  // namespace csgfit
