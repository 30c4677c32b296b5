// What a tree gets wrong against its target, and seed 000's score of it.
#pragma once

#include <cstddef>

namespace csgfit {

/// The mismatch between a tree's raster and the target, as in seed 000 (Figure 2).
struct Mismatch {
  std::size_t excess = 0;     ///< pixels the tree covers that are not in the target
  std::size_t uncovered = 0;  ///< target pixels the tree does not cover
  /// 3D only: voxels of the tree's bounding box beyond the grid (see TreeEvaluator3D), an
  /// excess the grid cannot see.
  std::size_t outside = 0;
  std::size_t total() const { return excess + uncovered + outside; }
};

inline Mismatch operator+(const Mismatch& a, const Mismatch& b) {
  return Mismatch{a.excess + b.excess, a.uncovered + b.uncovered, a.outside + b.outside};
}

/// Score of seed 000: excess + uncovered + k x primitives (lower is better).
inline double score(const Mismatch& m, std::size_t primitives, double k) {
  return static_cast<double>(m.total()) + k * static_cast<double>(primitives);
}

}  // namespace csgfit
