// Flat, incremental evaluation of a 3D CSG tree against a target voxel grid (the 3D twin of
// evaluator.h).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// Evaluates one 3D tree over the target's grid. The tree is flattened into a tape with one
/// bit-packed VoxelGrid per node; after a primitive changes only the grids on the path from
/// that leaf to the root are recomputed (update_leaf), so a local-optimiser step costs one scan
/// conversion plus a few whole-grid word operations per ancestor. Mismatch counts voxels.
///
/// The grid sees nothing beyond its box, so a tree that reaches out of it would be free there
/// and yet render there: Mismatch::outside counts, in voxels, the part of the tree's bounding
/// box (union = hull of the children's boxes, intersection = their overlap, difference = the
/// first child's box) that lies outside the grid's box. An upper bound of the true outside
/// volume, zero for every tree that stays in the grid, and growing smoothly as a primitive
/// moves out, so the optimisers are pushed back in.
///
/// The evaluator keeps pointers into `tree`; the tree's shape must not change while an
/// evaluator refers to it (parameter changes go through update_leaf).
class TreeEvaluator3D {
 public:
  /// Throws std::invalid_argument on an operator without children.
  TreeEvaluator3D(const VoxelGrid& target, Node3D& tree);
  /// Counts the mismatch on two samplings of the part: `target`, and `staggered`, the same part
  /// on a lattice shifted by a fraction of a voxel along every axis (voxelize's lattice_shift;
  /// the mesh polish uses 0.6). On one lattice a face can sit anywhere between two rows of
  /// centres at no cost, so a sheet of a primitive thinner than a voxel, or a slit between two,
  /// is invisible to it and yet renders; the staggered centres split the spacing and see it.
  /// Every mismatch this evaluator reports is the sum over both lattices (about twice one
  /// lattice's counts); result(), target() and the masks are those of `target`.
  TreeEvaluator3D(const VoxelGrid& target, const VoxelGrid& staggered, Node3D& tree);

  /// Whether a staggered lattice is counted too.
  bool staggered() const { return staggered_ != nullptr; }
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

  /// The tree's signed distance at a point, composed as signed_distance(const Node3D&, ...)
  /// does, with the leaves as they are now.
  double signed_distance(double x, double y, double z) const;

  /// Number of full or incremental evaluations done so far.
  std::size_t evaluations() const { return evaluations_; }

 private:
  // A block of x-rows: y indices [j0, j1] by z indices [k0, k1]. A change to one primitive
  // touches only the rows its old and new bounds cover, so updates cost in proportion to the
  // primitive's size, not the grid's.
  struct Rows {
    int j0 = 0, j1 = -1, k0 = 0, k1 = -1;
    bool empty() const { return j0 > j1 || k0 > k1; }
  };
  struct Slot {
    NodeKind kind;
    int parent;
    std::vector<int> children;
    Primitive3D* primitive;
    Rows rows;  // leaves: the rows their mask may have set
  };
  int build(Node3D& node, int parent);
  double signed_distance(int slot, double x, double y, double z) const;
  Rows rows_of(const Primitive3D& p) const;
  Rows all_rows() const;
  static Rows hull(const Rows& a, const Rows& b);
  static void clear_rows(VoxelGrid& g, const Rows& r);
  void combine(int slot, VoxelGrid& out, const Rows& r, int skip_child = -1,
               const VoxelGrid* replacement = nullptr);
  Mismatch measure(const VoxelGrid& raster, const Rows& r) const;
  // The mismatch if the root's rows r were those of changed_root.
  Mismatch delta(const VoxelGrid& changed_root, const Rows& r) const;
  const VoxelGrid& propagate_scratch(int slot, const VoxelGrid* mask, const Rows& r);
  // Voxels of the tree's bounding box outside the grid, with leaf slot `swap` replaced by
  // `replacement` (or removed when replacement is null); swap = -1 for the tree as it is.
  std::size_t outside_voxels(int swap, const Primitive3D* replacement) const;
  bool slot_bounds(int slot, int swap, const Primitive3D* replacement, Bounds3& out) const;

  const VoxelGrid& target_;
  std::vector<Slot> slots_;
  std::vector<VoxelGrid> masks_;
  std::vector<int> leaf_slots_;
  std::vector<Primitive3D*> leaf_prims_;
  int root_ = -1;
  Mismatch own_;       // this lattice's
  Mismatch mismatch_;  // own_ plus the staggered lattice's
  std::unique_ptr<TreeEvaluator3D> staggered_;
  std::size_t evaluations_ = 0;
  VoxelGrid scratch_leaf_;
  std::vector<VoxelGrid> scratch_path_;
};

}  // namespace csgfit
