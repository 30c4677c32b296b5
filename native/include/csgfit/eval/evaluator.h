// The flat, incremental evaluation of a CSG tree against a target grid, written once for 2D
// and 3D. evaluator2d.h and evaluator3d.h give it its grid (the "tape" policy: a region of
// rows, how a primitive is drawn) and add what only one dimension needs.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/model/tree.h"

namespace csgfit {

/// Evaluates one tree over a target grid. The tree is flattened into a tape with one
/// bit-packed grid (mask) per node. A change to one primitive touches only the rows its old
/// and new bounds cover (a Region), so an update re-draws the primitive there and recombines
/// its ancestors over those rows only, and the mismatch is corrected by the difference on
/// them: a local-optimiser step costs in proportion to the primitive's size, not the grid's.
///
/// The evaluator keeps pointers into `tree`; the tree's shape must not change while an
/// evaluator refers to it (parameter changes go through update_leaf).
///
/// `Tape` is the per-dimension part: `Grid`, `Primitive`, `Region` (a set of rows that is a
/// few contiguous runs of words), and static `region_of(primitive, target)`, `all_rows(target)`,
/// `hull(a, b)`, `for_each_run(region, grid, f(first_word, words))`, `rasterize_into(p, grid)`
/// and `blank_like(grid)`.
template <typename Tape>
class EvaluationTape {
 public:
  using Grid = typename Tape::Grid;
  using Prim = typename Tape::Primitive;
  using Region = typename Tape::Region;
  using Tree = CsgNode<Prim>;

  /// Throws std::invalid_argument on an operator without children.
  EvaluationTape(const Grid& target, Tree& tree);

  /// Mismatch of the current tree.
  const Mismatch& mismatch() const { return mismatch_; }
  /// The root's raster.
  const Grid& result() const { return masks_[static_cast<std::size_t>(root_)]; }
  const Grid& target() const { return target_; }
  std::size_t leaf_count() const { return leaf_slots_.size(); }
  /// Leaf i (pre-order) of the tree.
  Prim& leaf(std::size_t i) { return *leaf_prims_[i]; }
  /// The raster of leaf i alone.
  const Grid& leaf_mask(std::size_t i) const {
    return masks_[static_cast<std::size_t>(leaf_slots_[i])];
  }

  /// Re-draws leaf i (after its parameters were changed; normalises it first) and its
  /// ancestors; returns the new mismatch.
  const Mismatch& update_leaf(std::size_t i);
  /// Mismatch if leaf i were replaced by p, without changing anything.
  Mismatch try_leaf(std::size_t i, const Prim& p);
  /// Mismatch if leaf i were removed from its parent (as simplify would), without changing
  /// anything. A removed first child of a difference removes the whole difference.
  Mismatch try_without_leaf(std::size_t i);

  /// Number of full or incremental evaluations done so far.
  std::size_t evaluations() const { return evaluations_; }

 protected:
  struct Slot {
    NodeKind kind;
    int parent;
    std::vector<int> children;
    Prim* primitive;
    Region rows;  // leaves: the rows their mask may have set
  };

  const Slot& slot(int s) const { return slots_[static_cast<std::size_t>(s)]; }
  int leaf_slot(std::size_t i) const { return leaf_slots_[i]; }
  int root() const { return root_; }

 private:
  int build(Tree& node, int parent);
  Grid& mask(int s) { return masks_[static_cast<std::size_t>(s)]; }
  /// out = the operator of `slot` over its children's masks on the rows r, where skip_child
  /// takes `replacement` instead of its own mask, or is left out when that is null.
  void combine(int slot, Grid& out, const Region& r, int skip_child = -1,
               const Grid* replacement = nullptr) const;
  void clear(Grid& g, const Region& r) const;
  Mismatch measure(const Grid& raster, const Region& r) const;
  /// The mismatch if the root's rows r were those of changed_root.
  Mismatch delta(const Grid& changed_root, const Region& r) const;
  /// Recomputes the ancestors of `slot` on the rows r into scratch grids, with `slot` taking
  /// `mask` (or removed when mask is null), and returns the root's raster.
  const Grid& propagate_scratch(int slot, const Grid* mask, const Region& r);
  /// The rows a removal of leaf slot s can change.
  Region removal_rows(int s) const;

  const Grid& target_;
  std::vector<Slot> slots_;
  std::vector<Grid> masks_;
  std::vector<int> leaf_slots_;
  std::vector<Prim*> leaf_prims_;
  int root_ = -1;
  Mismatch mismatch_;
  std::size_t evaluations_ = 0;
  Grid scratch_leaf_;
  std::vector<Grid> scratch_path_;
};

}  // namespace csgfit
