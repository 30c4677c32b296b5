// The trees, targets and perturbations the micro-benchmarks share, in 2D (Flat) and 3D (Solid)
// behind one interface, so that every benchmark of a case sees the same tree and the same moves.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"
#include "random_trees.h"
#include "random_trees3d.h"

namespace csgfit::bench {

/// 2D: trees over a size x size bitmap.
struct Flat {
  using Tree = Node;
  using Grid = Bitmap;
  using Prim = Primitive;
  using Evaluator = TreeEvaluator;

  static Tree random_tree(std::mt19937_64& rng, int size, int depth) {
    return testing::random_tree(rng, size, size, depth);
  }
  static Grid frame(int size) { return Bitmap(size, size); }
  static Grid render(const Tree& tree, const Grid& frame) {
    return csgfit::render(tree, frame.width(), frame.height());
  }
  static std::size_t cells(const Grid& g) {
    return static_cast<std::size_t>(g.width()) * static_cast<std::size_t>(g.height());
  }
  /// Moves one parameter as a step of the local optimiser does: the centre or a size by up to
  /// 4 pixels, or the angle by up to 8 degrees.
  static Prim perturb(std::mt19937_64& rng, Prim p) {
    const double step = steps(rng);
    switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
      case 0: p.cx += step; break;
      case 1: p.cy += step; break;
      case 2: p.w += step; break;
      case 3: p.h += step; break;
      default: p.angle += 2 * step; break;
    }
    p.normalize();
    return p;
  }
  static double steps(std::mt19937_64& rng) {
    static const double table[] = {-4, -2, -1, -0.5, 0.5, 1, 2, 4};
    return table[std::uniform_int_distribution<int>(0, 7)(rng)];
  }
};

/// 3D: trees over a size^3 grid of unit voxels.
struct Solid {
  using Tree = Node3D;
  using Grid = VoxelGrid;
  using Prim = Primitive3D;
  using Evaluator = TreeEvaluator3D;

  static Tree random_tree(std::mt19937_64& rng, int size, int depth) {
    return testing::random_tree3d(rng, size, depth);
  }
  static Grid frame(int size) { return VoxelGrid(size, size, size); }
  static Grid render(const Tree& tree, const Grid& frame) { return csgfit::render(tree, frame); }
  static std::size_t cells(const Grid& g) {
    return static_cast<std::size_t>(g.nx()) * static_cast<std::size_t>(g.ny()) *
           static_cast<std::size_t>(g.nz());
  }
  /// The centre or a dimension by up to 4 voxels (a turn costs the same scan conversion).
  static Prim perturb(std::mt19937_64& rng, Prim p) {
    const double step = Flat::steps(rng);
    const int which = std::uniform_int_distribution<int>(0, 5)(rng);
    if (which < 3) {
      (which == 0 ? p.cx : which == 1 ? p.cy : p.cz) += step;
    } else {
      p.dims[static_cast<std::size_t>(which - 3)] += step;
    }
    p.normalize();
    return p;
  }
};

/// Leaf `leaf` (pre-order) replaced by `prim`.
template <class D>
struct Move {
  std::size_t leaf;
  typename D::Prim prim;
};

/// One benchmark case: a tree with a given number of leaves, its own raster as the target (so a
/// move is scored as near convergence, where the search spends its time) and the moves tried.
template <class D>
struct Case {
  typename D::Tree tree;
  typename D::Grid target;
  std::vector<Move<D>> moves;
  /// Why the incremental and the plain evaluator disagree on this case; empty when they agree.
  std::string error;
};

/// Moves per case: enough that the timed loops cycle through many leaves and kinds.
inline constexpr std::size_t kMoves = 32;

/// random_tree draws the depth, not the leaf count: the case takes the first tree (in the draw
/// order of `seed`) with exactly `leaves` leaves whose raster covers 5 to 95 % of the grid.
/// Primitives scale with the grid and the draws do not depend on its size, so the same seed
/// gives the same tree, scaled, at every size: the tree is picked on the smallest grid and
/// drawn again at `size`.
template <class D>
typename D::Tree tree_with_leaves(std::size_t leaves, int size, std::uint64_t seed) {
  const int depth = std::max(1, static_cast<int>(std::ceil(std::log2(static_cast<double>(leaves)))));
  constexpr int kPickSize = 32;
  const typename D::Grid pick_frame = D::frame(kPickSize);
  std::mt19937_64 rng(seed);
  for (long draw = 0; draw < 1000000; ++draw) {
    const typename D::Tree t = D::random_tree(rng, kPickSize, depth);
    if (t.primitive_count() != leaves) continue;
    const double covered = static_cast<double>(D::render(t, pick_frame).count()) /
                           static_cast<double>(D::cells(pick_frame));
    if (covered < 0.05 || covered > 0.95) continue;
    std::mt19937_64 again(seed);
    for (long i = 0; i < draw; ++i) D::random_tree(again, size, depth);
    return D::random_tree(again, size, depth);
  }
  throw std::runtime_error("no random tree with " + std::to_string(leaves) + " leaves");
}

template <class D>
Case<D> make_case(std::size_t leaves, int size, std::uint64_t seed) {
  Case<D> c;
  c.tree = tree_with_leaves<D>(leaves, size, seed);
  c.target = D::render(c.tree, D::frame(size));
  const auto prims = csgfit::leaves(c.tree);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  for (std::size_t k = 0; k < kMoves; ++k) {
    const std::size_t leaf = std::uniform_int_distribution<std::size_t>(0, prims.size() - 1)(rng);
    c.moves.push_back({leaf, D::perturb(rng, *prims[leaf])});
  }
  return c;
}

/// Google Benchmark calls a benchmark function several times while it sizes the iteration
/// count: a case (and its check, often hundreds of full renders) is made once per pair of
/// arguments, by `make(a, b)`, and shared by every benchmark of the same pair.
template <class Value, class Make>
const Value& cached(std::int64_t a, std::int64_t b, Make&& make) {
  static std::map<std::pair<std::int64_t, std::int64_t>, Value> cases;
  const auto key = std::make_pair(a, b);
  auto it = cases.find(key);
  if (it == cases.end()) it = cases.emplace(key, make(a, b)).first;
  return it->second;
}

/// Seed 000's evaluation: scan-convert every primitive, combine the whole tree, count.
template <class D>
Mismatch plain_mismatch(const typename D::Tree& tree, const typename D::Grid& target) {
  const typename D::Grid raster = D::render(tree, target);
  return {count_and_not(raster, target), count_and_not(target, raster)};
}

/// The plain evaluator sees only the grid, so Mismatch::outside (3D: the part of the tree's
/// bounding box beyond the grid) is not compared.
inline bool same_counts(const Mismatch& a, const Mismatch& b) {
  return a.excess == b.excess && a.uncovered == b.uncovered;
}

inline std::string describe(const Mismatch& m) {
  return "excess " + std::to_string(m.excess) + ", uncovered " + std::to_string(m.uncovered);
}

}  // namespace csgfit::bench
