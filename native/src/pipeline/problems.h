// Internal to pipeline/: one target's search problem and first trees, shared by the fits
// (fit_bitmap.cpp, fit_voxels.cpp) and the morphs (fit_morph.cpp), which search two targets.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>

#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "search/operators2d.h"
#include "search/operators3d.h"

namespace csgfit {

/// The 2D search problem of `target`: its size weight, kinds, distance peaks and the local
/// optimiser's settings (whose deadline is the end of the budget that began at `start`).
Problem2D make_problem2d(const Bitmap& target, const FitOptions& options,
                         std::chrono::steady_clock::time_point start);

/// The two deterministic first trees of a 2D search, scored as the search scores its trees
/// (a candidate without primitives where a seed does not apply).
struct SeedTrees2D {
  Candidate2D decomposition;  ///< seed 003, locally optimised
  Candidate2D greedy;         ///< the greedy residual cover
  Candidate2D selection;      ///< the boundary's primitives chosen as unions and cuts
  /// The seeds that exist (a tree with primitives), in this order.
  std::vector<const Candidate2D*> present() const {
    std::vector<const Candidate2D*> out;
    for (const Candidate2D* c : {&decomposition, &greedy, &selection})
      if (c->primitives > 0) out.push_back(c);
    return out;
  }
};
SeedTrees2D seed_trees2d(const Bitmap& target, const FitOptions& options, const Problem2D& pb,
                         Operators2D& ops, std::chrono::steady_clock::time_point start,
                         std::size_t& evaluations);

/// The 3D search problem of `target` (see make_problem2d).
Problem3D make_problem3d(const VoxelGrid& target, const FitOptions3D& options,
                         std::chrono::steady_clock::time_point start,
                         const std::atomic<bool>* cancel);

/// Seed 003's 3D decomposition of `target`, every leaf optimised (unscored, unpruned);
/// `polish_seconds` gets how long the optimisation took.
Node3D first_tree3d(const VoxelGrid& target, const FitOptions3D& options, const Problem3D& pb,
                    std::chrono::steady_clock::time_point start, const std::atomic<bool>* cancel,
                    std::size_t& evaluations, double* polish_seconds = nullptr);

}  // namespace csgfit
