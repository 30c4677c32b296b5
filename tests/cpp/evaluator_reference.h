// The brute-force references the evaluator tests compare against, one per dimension: random
// trees on a fixed frame and the obviously-correct raster, one pixel or voxel centre at a time.
#pragma once

#include <algorithm>
#include <cstddef>
#include <random>
#include <vector>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/tree3d.h"

namespace csgfit::reference {

/// A random operator node over random subtrees: the tree shapes both dimensions test on.
template <typename Tree, typename RandomLeaf>
Tree random_tree(std::mt19937_64& rng, int depth, const RandomLeaf& random_leaf) {
  if (depth == 0 || rng() % 4 == 0) return Tree::leaf(random_leaf(rng));
  static const NodeKind ops[3] = {NodeKind::Union, NodeKind::Difference, NodeKind::Intersection};
  std::vector<Tree> children;
  const int n = 2 + static_cast<int>(rng() % 3);
  for (int i = 0; i < n; ++i) children.push_back(random_tree<Tree>(rng, depth - 1, random_leaf));
  return Tree::op(ops[rng() % 3], std::move(children));
}

template <typename Grid>
Mismatch mismatch_of(const Grid& raster, const Grid& target) {
  return {count_and_not(raster, target), count_and_not(target, raster)};
}

/// A random 3D primitive of `kind` (in PrimitiveKind3D order, then 7 and 8 for the polygonal
/// cylinder and cone of 3 to 12 sides, 9 for the rounded box) centred in the box [lo, hi], its
/// sizes in [dim_lo, dim_hi], under a uniformly random rotation; a third of the round cones are
/// pointed, a third of the rounded boxes stadiums.
inline Primitive3D random_primitive3d(std::mt19937_64& rng, int kind, const Vec3& lo, const Vec3& hi,
                                      double dim_lo, double dim_hi) {
  std::uniform_real_distribution<double> dim(dim_lo, dim_hi), apex(-1, 1), unit(0, 1);
  std::normal_distribution<double> g(0, 1);
  Quaternion q{g(rng), g(rng), g(rng), g(rng)};
  q.normalize();
  double c[3];
  for (int i = 0; i < 3; ++i) c[i] = std::uniform_real_distribution<double>(lo[i], hi[i])(rng);
  const double x = c[0], y = c[1], z = c[2];
  switch (kind) {
    case 0: return Primitive3D::box(x, y, z, dim(rng), dim(rng), dim(rng), q);
    case 1: return Primitive3D::sphere(x, y, z, dim(rng) / 2);
    case 2: return Primitive3D::cylinder(x, y, z, dim(rng) / 2, dim(rng), q);
    case 3: {
      const double r2 = unit(rng) < 0.3 ? 0 : dim(rng) / 3;
      return Primitive3D::cone(x, y, z, dim(rng) / 2, r2, dim(rng), q);
    }
    case 4: return Primitive3D::ellipsoid(x, y, z, dim(rng) / 2, dim(rng) / 2, dim(rng) / 3, q);
    case 5: {
      const double major = dim(rng) / 2;
      return Primitive3D::torus(x, y, z, major, major * (0.25 + 0.6 * unit(rng)), q);
    }
    case 6: return Primitive3D::prism(x, y, z, dim(rng), dim(rng), dim(rng), apex(rng), q);
    case 9: {
      const double sx = dim(rng), sy = dim(rng), most = std::min(sx, sy) / 2;
      const double corner = unit(rng) < 0.3 ? most : most * (0.1 + 0.8 * unit(rng));
      return Primitive3D::rounded_box(x, y, z, sx, sy, dim(rng), corner, q);
    }
    default: {
      Primitive3D p =
          kind == 7 ? Primitive3D::cylinder(x, y, z, dim(rng) / 2, dim(rng), q)
                    : Primitive3D::cone(x, y, z, dim(rng) / 2, dim(rng) / 3, dim(rng), q);
      p.sides = 3 + static_cast<int>(rng() % 10);
      return p;
    }
  }
}

/// 2D: a 64 x 64 canvas of unit pixels.
struct Flat {
  using Tree = Node;
  using Evaluator = TreeEvaluator;
  static constexpr int kRenderTrials = 200, kUpdateTrees = 60, kUpdateSteps = 20,
                       kRemovalTrials = 100, kSimplifyTrials = 200;
  static constexpr std::size_t kMinCovered = 30000;  // of 819200: the trees are not all empty

  static Primitive random_primitive(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> pos(5, 59), dim(3, 30), ang(0, 360), apex(-1, 1);
    switch (rng() % 4) {
      case 0:
        return Primitive::rectangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng));
      case 1:
        return Primitive::circle(pos(rng), pos(rng), dim(rng) / 2);
      case 2:
        return Primitive::ellipse(pos(rng), pos(rng), dim(rng) / 2, dim(rng) / 2, ang(rng));
      default:
        return Primitive::triangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng), apex(rng));
    }
  }
  static Node random_tree(std::mt19937_64& rng, int depth) {
    return reference::random_tree<Node>(rng, depth, random_primitive);
  }
  static Bitmap empty() { return Bitmap(64, 64); }
  static Bitmap render(const Node& t) { return csgfit::render(t, 64, 64); }
  static Bitmap brute_force(const Node& t) {
    Bitmap b = empty();
    for (int r = 0; r < 64; ++r)
      for (int c = 0; c < 64; ++c)
        if (inside(t, c + 0.5, 64 - r - 0.5)) b.set(c, r);
    return b;
  }

 private:
  static bool inside(const Node& n, double x, double y) {
    if (n.is_leaf()) return n.primitive.contains(x, y);
    bool v = inside(n.children[0], x, y);
    for (std::size_t i = 1; i < n.children.size(); ++i) {
      const bool c = inside(n.children[i], x, y);
      switch (n.kind) {
        case NodeKind::Union:
          v = v || c;
          break;
        case NodeKind::Difference:
          v = v && !c;
          break;
        case NodeKind::Intersection:
          v = v && c;
          break;
        default:
          break;
      }
    }
    return v;
  }
};

/// 3D: a 40 x 36 x 32 grid of half-unit voxels off the origin, so that the frame's placement
/// is part of what is tested.
struct Solid {
  using Tree = Node3D;
  using Evaluator = TreeEvaluator3D;
  static constexpr int kRenderTrials = 120, kUpdateTrees = 30, kUpdateSteps = 12,
                       kRemovalTrials = 60, kSimplifyTrials = 100;
  static constexpr std::size_t kMinCovered = 10000;
  static constexpr int kNx = 40, kNy = 36, kNz = 32;

  static VoxelGrid frame() { return VoxelGrid(kNx, kNy, kNz, -1.0, 0.5, 2.0, 0.5); }
  static Primitive3D random_primitive(std::mt19937_64& rng) {
    const int kind = static_cast<int>(rng() % 10);
    return random_primitive3d(rng, kind, {2, 3, 4}, {17, 16, 16}, 2, 12);
  }
  static Node3D random_tree(std::mt19937_64& rng, int depth) {
    return reference::random_tree<Node3D>(rng, depth, random_primitive);
  }
  static VoxelGrid empty() {
    VoxelGrid g = frame();
    g.clear();
    return g;
  }
  static VoxelGrid render(const Node3D& t) { return csgfit::render(t, frame()); }
  static VoxelGrid brute_force(const Node3D& t) {
    VoxelGrid g = empty();
    for (int k = 0; k < kNz; ++k)
      for (int j = 0; j < kNy; ++j)
        for (int i = 0; i < kNx; ++i)
          if (contains(t, g.center_x(i), g.center_y(j), g.center_z(k))) g.set(i, j, k);
    return g;
  }
};

}  // namespace csgfit::reference
