// Flat, incremental evaluation of a 3D CSG tree against a target voxel grid.
#pragma once

#include <cstddef>
#include <memory>

#include "csgfit/eval/evaluator.h"
#include "csgfit/eval/mismatch.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// The 3D part of the tape: a region is a block of x-rows, y indices [j0, j1] by z indices
/// [k0, k1]; the rows of one z-slab are contiguous, so a region is one run of words per slab.
struct VoxelTape {
  using Grid = VoxelGrid;
  using Primitive = Primitive3D;
  struct Region {
    int j0 = 0, j1 = -1, k0 = 0, k1 = -1;
    bool empty() const { return j0 > j1 || k0 > k1; }
  };

  static Region region_of(const Primitive3D& p, const VoxelGrid& target);
  static Region all_rows(const VoxelGrid& target) {
    return Region{0, target.ny() - 1, 0, target.nz() - 1};
  }
  static Region hull(const Region& a, const Region& b);
  template <typename F>
  static void for_each_run(const Region& r, const VoxelGrid& grid, F&& f) {
    if (r.empty()) return;
    const std::size_t wpr = static_cast<std::size_t>(grid.words_per_row());
    const std::size_t ny = static_cast<std::size_t>(grid.ny());
    const std::size_t span = (static_cast<std::size_t>(r.j1 - r.j0) + 1) * wpr;
    for (int k = r.k0; k <= r.k1; ++k)
      f((static_cast<std::size_t>(k) * ny + static_cast<std::size_t>(r.j0)) * wpr, span);
  }
  static void rasterize_into(const Primitive3D& p, VoxelGrid& grid);
  static VoxelGrid blank_like(const VoxelGrid& target);
};

/// Evaluates one 3D tree over the target's grid (see EvaluationTape); mismatch counts voxels.
///
/// The grid sees nothing beyond its box, so a tree that reaches out of it would be free there
/// and yet render there: Mismatch::outside counts, in voxels, the part of the tree's bounding
/// box (union = hull of the children's boxes, intersection = their overlap, difference = the
/// first child's box) that lies outside the grid's box. An upper bound of the true outside
/// volume, zero for every tree that stays in the grid, and growing smoothly as a primitive
/// moves out, so the optimisers are pushed back in.
class TreeEvaluator3D : public EvaluationTape<VoxelTape> {
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
  /// Mismatch of the current tree: both lattices, and the tree beyond the grid.
  const Mismatch& mismatch() const { return mismatch_; }

  /// As EvaluationTape's, with the outside count and the staggered lattice added.
  const Mismatch& update_leaf(std::size_t i);
  Mismatch try_leaf(std::size_t i, const Primitive3D& p);
  Mismatch try_without_leaf(std::size_t i);

  /// The tree's signed distance at a point, composed as signed_distance(const Node3D&, ...)
  /// does, with the leaves as they are now.
  double signed_distance(double x, double y, double z) const;
  /// The leaf whose surface that distance comes from: the primitive that makes the tree's
  /// boundary there (leaf_count() for an empty tree); the distance itself in `distance`.
  std::size_t surface_leaf(double x, double y, double z, double* distance = nullptr) const;

 private:
  // `from` receives the slot of the primitive that gave the distance.
  double signed_distance(int slot, double x, double y, double z, int& from) const;
  // Voxels of the tree's bounding box outside the grid, with leaf slot `swap` replaced by
  // `replacement` (or removed when replacement is null); swap = -1 for the tree as it is.
  std::size_t outside_voxels(int swap, const Primitive3D* replacement) const;
  bool slot_bounds(int slot, int swap, const Primitive3D* replacement, Bounds3& out) const;

  Mismatch mismatch_;  // this lattice's (with outside) plus the staggered lattice's
  std::unique_ptr<TreeEvaluator3D> staggered_;
};

}  // namespace csgfit
