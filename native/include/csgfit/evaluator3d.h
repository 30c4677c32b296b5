// Flat, incremental evaluation of a 3D CSG tree against a target voxel grid (the 3D twin of
// evaluator.h).
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/evaluator.h"
#include "csgfit/tree3d.h"
#include "csgfit/voxel_grid.h"

namespace csgfit {

/// Evaluates one 3D tree over the target's grid. The tree is flattened into a tape with one
/// bit-packed VoxelGrid per node; after a primitive changes only the grids on the path from
/// that leaf to the root are recomputed (update_leaf), so a local-optimiser step costs one scan
/// conversion plus a few whole-grid word operations per ancestor. Mismatch counts voxels.
///
/// The evaluator keeps pointers into `tree`; the tree's shape must not change while an
/// evaluator refers to it (parameter changes go through update_leaf).
class TreeEvaluator3D {
 public:
  /// Throws std::invalid_argument on an operator without children.
  TreeEvaluator3D(const VoxelGrid& target, Node3D& tree);

  /// Mismatch of the current tree.
  const Mismatch& mismatch() const { return mismatch_; }
  /// The root's voxels.
  const VoxelGrid& result() const { return masks_[root_]; }
  const VoxelGrid& target() const { return target_; }
  std::size_t leaf_count() const { return leaf_slots_.size(); }
  /// Leaf i (pre-order) of the tree.
  Primitive3D& leaf(std::size_t i) { return *leaf_prims_[i]; }
  /// The voxels of leaf i alone.
  const VoxelGrid& leaf_mask(std::size_t i) const { return masks_[leaf_slots_[i]]; }

  /// Re-rasterises leaf i (after its parameters were changed; normalises it first) and its
  /// ancestors; returns the new mismatch.
  const Mismatch& update_leaf(std::size_t i);
  /// Mismatch if leaf i were replaced by p, without changing anything.
  Mismatch try_leaf(std::size_t i, const Primitive3D& p);
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
    Primitive3D* primitive;
  };
  int build(Node3D& node, int parent);
  void combine(int slot, VoxelGrid& out, int skip_child = -1,
               const VoxelGrid* replacement = nullptr);
  Mismatch measure(const VoxelGrid& raster) const;
  const VoxelGrid& propagate_scratch(int slot, const VoxelGrid* mask);

  const VoxelGrid& target_;
  std::vector<Slot> slots_;
  std::vector<VoxelGrid> masks_;
  std::vector<int> leaf_slots_;
  std::vector<Primitive3D*> leaf_prims_;
  int root_ = -1;
  Mismatch mismatch_;
  std::size_t evaluations_ = 0;
  VoxelGrid scratch_leaf_;
  std::vector<VoxelGrid> scratch_path_;
};

}  // namespace csgfit
