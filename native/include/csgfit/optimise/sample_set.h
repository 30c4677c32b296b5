// Seed 001's sampling (Sec. 5.1.1): points over the halfspaces' bounds, coarse to fine, with
// every halfspace's inside test stored as a bit column, so that an expression's point set is
// a few word operations and the empty-set decision stops at the first level that has an
// inside point. Proven-empty expressions are cached.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/halfspace.h"

namespace csgfit::opt {

/// One bit per sample point, 64 a word.
using Column = std::vector<std::uint64_t>;

struct SamplingOptions {
  std::uint64_t seed = 1;
  std::size_t finest = 0;  ///< points per axis of the finest global level (0: 48 in 3D, 256 in 2D)
  std::size_t local = 0;   ///< points per axis in each halfspace's own box (0: 8 in 3D, 24 in 2D)
};

/// Most halfspaces a tree may have for optimisation: the columns take points x halfspaces bits.
constexpr std::size_t kMaxHalfspaces = 5000;

template <std::size_t D>
class SampleSet {
 public:
  /// Throws InputError when there are more than kMaxHalfspaces halfspaces.
  SampleSet(const HalfspaceList<D>& halfspaces, const SamplingOptions& options);

  std::size_t point_count() const { return points_.size(); }
  std::size_t word_count() const { return points_.size() / 64; }
  const Point<D>& point(std::size_t i) const { return points_[i]; }
  const Column& column(int halfspace) const { return columns_[static_cast<std::size_t>(halfspace)]; }
  std::size_t halfspace_count() const { return columns_.size(); }

  /// The expression's samples (no opaque leaves allowed: std::logic_error).
  Column evaluate(const Expr& e) const;
  /// Whether the expression is empty: no shared sample is inside (level by level, stopping at
  /// the first inside one), and neither is any of a dense jittered grid over the expression's
  /// own bounds (the seed's minimum cell size, where it matters: a thin sliver between two
  /// large primitives falls between the shared samples). Cached by structure.
  bool is_empty(const Expr& e) const;
  /// Conservative bounds of the expression's solid; `empty` when they are empty.
  Box<D> bounds_of(const Expr& e, bool& empty) const;
  /// Number of empty-set decisions asked and answered from the cache.
  std::size_t decisions() const { return decisions_; }
  std::size_t cache_hits() const { return cache_hits_; }

 private:
  Column evaluate_range(const Expr& e, std::size_t w0, std::size_t w1) const;
  bool dense_empty(const Expr& e) const;
  const HalfspaceList<D>* halfspaces_ = nullptr;
  Box<D> domain_;
  std::uint64_t seed_ = 1;
  std::vector<Point<D>> points_;
  std::vector<std::size_t> level_words_;  // word index where each level ends
  std::vector<Column> columns_;
  mutable std::unordered_map<std::uint64_t, bool> empty_cache_;
  mutable std::size_t decisions_ = 0, cache_hits_ = 0;
};

/// Whether the point is inside the expression, tested pointwise (no opaque leaves allowed:
/// std::logic_error).
template <std::size_t D>
bool contains(const Expr& e, const HalfspaceList<D>& halfspaces, const Point<D>& p);

/// Whether any bit is set.
bool any(const Column& c);
/// a & ~b has a bit set.
bool any_outside(const Column& a, const Column& b);
/// a & b has a bit set.
bool any_common(const Column& a, const Column& b);

extern template class SampleSet<2>;
extern template class SampleSet<3>;

}  // namespace csgfit::opt
