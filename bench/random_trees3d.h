// Random 3D CSG trees, the 3D twin of tests/cpp/random_trees.h (which has only 2D ones): the
// same kinds of operators and the same tree shapes, with primitives kept inside the grid.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "csgfit/model/tree3d.h"

namespace csgfit::testing {

/// A random primitive of any kind inside a grid of n^3 unit voxels with its corner at the
/// origin. Smaller and more central than the 2D ones, whose corners may leave the canvas: a
/// solid that leaves the grid is scored by its bounding box there (Mismatch::outside), which
/// no optimiser can remove from a tree fitted to its own raster.
inline Primitive3D random_primitive3d(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> centre(0.25 * n, 0.75 * n);
  const double scale = 0.5 * n;
  std::uniform_real_distribution<double> size(0.12 * scale, 0.5 * scale);
  std::uniform_real_distribution<double> apex(-1.2, 1.2), unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  Quaternion q{gauss(rng), gauss(rng), gauss(rng), gauss(rng)};
  q.normalize();
  const double x = centre(rng), y = centre(rng), z = centre(rng);
  switch (std::uniform_int_distribution<int>(0, 6)(rng)) {
    case 0: return Primitive3D::box(x, y, z, size(rng), size(rng), size(rng), q);
    case 1: return Primitive3D::sphere(x, y, z, size(rng) / 2);
    case 2: return Primitive3D::cylinder(x, y, z, size(rng) / 2, size(rng), q);
    case 3: return Primitive3D::cone(x, y, z, size(rng) / 2, size(rng) / 4, size(rng), q);
    case 4:
      return Primitive3D::ellipsoid(x, y, z, size(rng) / 2, size(rng) / 2, size(rng) / 2, q);
    case 5: {
      const double major = size(rng) / 2;
      return Primitive3D::torus(x, y, z, major, major * (0.2 + 0.7 * unit(rng)), q);
    }
    default: return Primitive3D::prism(x, y, z, size(rng), size(rng), size(rng), apex(rng), q);
  }
}

/// A random tree with up to `depth` operator levels, 2-3 children per operator.
inline Node3D random_tree3d(std::mt19937_64& rng, int n, int depth) {
  if (depth <= 0 || std::uniform_int_distribution<int>(0, 3)(rng) == 0)
    return Node3D::leaf(random_primitive3d(rng, n));
  static const NodeKind kinds[] = {NodeKind::Union, NodeKind::Union, NodeKind::Difference,
                                   NodeKind::Intersection};
  const NodeKind kind = kinds[std::uniform_int_distribution<int>(0, 3)(rng)];
  const int count = std::uniform_int_distribution<int>(2, 3)(rng);
  std::vector<Node3D> children;
  for (int i = 0; i < count; ++i) children.push_back(random_tree3d(rng, n, depth - 1));
  return Node3D::op(kind, std::move(children));
}

}  // namespace csgfit::testing
