// Flat, incremental evaluation of a CSG tree against a target bitmap.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"

namespace csgfit {


/// Evaluates one tree over a canvas. The tree is flattened into a post-order tape with one
/// bit-packed mask per node; after a primitive changes, only the masks on the path from that
/// leaf to the root are recomputed (update_leaf), so a local-optimiser step costs one scan
/// conversion plus a few whole-word operations per ancestor.
///
/// The evaluator keeps pointers into `tree`; the tree's shape must not change while an
/// evaluator refers to it (parameter changes go through update_leaf).
class TreeEvaluator {
 public:
  TreeEvaluator(const Bitmap& target, Node& tree);

  /// Mismatch of the current tree.
  const Mismatch& mismatch() const { return mismatch_; }
  /// The root's raster.
  const Bitmap& result() const { return masks_[root_]; }
  std::size_t leaf_count() const { return leaf_slots_.size(); }
  /// Leaf i (pre-order) of the tree.
  Primitive& leaf(std::size_t i) { return *leaf_prims_[i]; }
  /// The raster of leaf i alone.
  const Bitmap& leaf_mask(std::size_t i) const { return masks_[leaf_slots_[i]]; }

  /// Re-rasterises leaf i (after its parameters were changed) and its ancestors; returns the
  /// new mismatch.
  const Mismatch& update_leaf(std::size_t i);
  /// Mismatch if leaf i were replaced by p, without changing anything.
  Mismatch try_leaf(std::size_t i, const Primitive& p);
  /// Mismatch if leaf i were removed from its parent (as simplify would), without changing
  /// anything. A removed first child of a difference removes the whole difference.
  Mismatch try_without_leaf(std::size_t i);

  /// Number of full or incremental evaluations done so far.
  std::size_t evaluations() const { return evaluations_; }

 private:
  struct Slot {
    NodeKind kind;
    int parent;
    std::vector<int> children;
    Primitive* primitive;
  };
  /// Rows [begin, end) outside which a mask is known to be empty.
  struct Rows {
    int begin = 0, end = 0;
  };
  int build(Node& node, int parent);
  /// out = the operator of `slot` over its children's masks, where skip_child takes
  /// `replacement` (with its rows) instead of its own mask, or is left out when that is null.
  void combine(int slot, Bitmap& out, Rows& out_rows, int skip_child,
               const Bitmap* replacement, Rows replacement_rows);
  Mismatch measure(const Bitmap& raster) const;
  /// Recomputes the ancestors of `slot` into scratch buffers, with `slot` taking `mask` (or
  /// being removed when mask is null), and returns the root's raster.
  const Bitmap& propagate_scratch(int slot, const Bitmap* mask, Rows rows);

  const Bitmap& target_;
  std::vector<Slot> slots_;
  std::vector<Bitmap> masks_;
  std::vector<Rows> rows_;
  std::vector<int> leaf_slots_;
  std::vector<Primitive*> leaf_prims_;
  int root_ = -1;
  Mismatch mismatch_;
  std::size_t evaluations_ = 0;
  Bitmap scratch_leaf_;
  std::vector<Bitmap> scratch_path_;
  std::vector<Rows> scratch_rows_;
};

}  // namespace csgfit
