// Two shapes -> two CSG trees of one structure, for morphing (seed 000, "Application to
// geometric morphing"): the pair search behind one call per dimension, for the CLI (csgfit
// morph) and the Python module.
#pragma once

#include <atomic>
#include <utility>
#include <vector>

#include "csgfit/model/interpolate.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

/// Where a primitive of the pair is seen: a primitive seen in one shape only has zero size in
/// the other, at a point of its partner (so the morph grows it from there or shrinks it to it).
struct MorphLeaf {
  bool in_a = true, in_b = true;
};

/// Two trees of one structure and how each matches its own target.
template <typename Tree>
struct MorphPair {
  Tree a, b;                     ///< same operators and primitive kinds, leaf for leaf
  FitStats stats_a, stats_b;     ///< each against its own target; the search's counters in both
  std::vector<MorphLeaf> leaves; ///< per leaf, in pre-order
};

/// A 2D morph's options: the fit's (the paper preset: SearchParams::for_morph("paper")) and the
/// direction each primitive turns.
struct MorphOptions {
  FitOptions fit;
  TurnDirection rotate = TurnDirection::Shortest;
};

/// A 2D morph: trees in pixel units, y up, on the targets' common canvas. b's angles end the
/// turns from a's (choose_turns), so interpolate(a, b, t) is the morph at t.
struct MorphResult : MorphPair<Node> {
  int width = 0, height = 0;
};

/// Searches a pair of trees for bitmaps `a` and `b` (same size; a fit option error or an empty
/// target throws std::invalid_argument naming which). Honours `cancel` and the progress
/// callback as fit_bitmap does.
MorphResult morph_bitmaps(const Bitmap& a, const Bitmap& b, const MorphOptions& options,
                          const ProgressCallback& progress = nullptr,
                          const std::atomic<bool>* cancel = nullptr);

/// A 3D morph: trees in the grid's model coordinates.
struct MorphResult3D : MorphPair<Node3D> {};

/// The two inputs of a 3D morph on one lattice: two meshes voxelised over the box of both,
/// `resolution` voxels along its longest side (0 = 64); two voxel grids as they are, which must
/// already share one. Throws InputError for a mesh and a grid, or grids that differ.
std::pair<VoxelGrid, VoxelGrid> morph_grids(const Input3D& a, const Input3D& b, int resolution);

/// Searches a pair of trees for voxel grids `a` and `b`, which must share their lattice (same
/// size, origin and voxel edge: morph_grids puts two meshes on one). Starts from seed
/// 003's decomposition of each, copied into both trees.
MorphResult3D morph_voxels(const VoxelGrid& a, const VoxelGrid& b, const FitOptions3D& options,
                           const ProgressCallback& progress = nullptr,
                           const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
