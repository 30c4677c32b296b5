// Random and hand-made CSG trees for the export tests (JSON, .scad, OpenSCAD round trip).
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "csgfit/model/tree2d.h"

namespace csgfit::testing {

/// A random primitive of any kind, sized for a canvas of the given size (pixel units).
inline Primitive random_primitive(std::mt19937_64& rng, int width, int height) {
  std::uniform_real_distribution<double> ux(0.15 * width, 0.85 * width);
  std::uniform_real_distribution<double> uy(0.15 * height, 0.85 * height);
  const double scale = 0.5 * std::min(width, height);
  std::uniform_real_distribution<double> size(0.12 * scale, 0.8 * scale);
  std::uniform_real_distribution<double> angle(0, 360);
  std::uniform_real_distribution<double> apex(-1.2, 1.2);
  switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0: return Primitive::rectangle(ux(rng), uy(rng), size(rng), size(rng), angle(rng));
    case 1: return Primitive::circle(ux(rng), uy(rng), size(rng) / 2);
    case 2: return Primitive::ellipse(ux(rng), uy(rng), size(rng) / 2, size(rng) / 2, angle(rng));
    default:
      return Primitive::triangle(ux(rng), uy(rng), size(rng), size(rng), angle(rng), apex(rng));
  }
}

/// A random tree with up to `depth` operator levels, 2-3 children per operator.
inline Node random_tree(std::mt19937_64& rng, int width, int height, int depth) {
  if (depth <= 0 || std::uniform_int_distribution<int>(0, 3)(rng) == 0)
    return Node::leaf(random_primitive(rng, width, height));
  static const NodeKind kinds[] = {NodeKind::Union, NodeKind::Union, NodeKind::Difference,
                                   NodeKind::Intersection};
  const NodeKind kind = kinds[std::uniform_int_distribution<int>(0, 3)(rng)];
  const int n = std::uniform_int_distribution<int>(2, 3)(rng);
  std::vector<Node> children;
  for (int i = 0; i < n; ++i) children.push_back(random_tree(rng, width, height, depth - 1));
  return Node::op(kind, std::move(children));
}

/// The hand-made tree of the round-trip test on a 96 x 80 canvas: (rect - circle) + rotated
/// ellipse + triangle + (circle & rotated rectangle), with a nested union to flatten.
inline Node sample_tree() {
  Node plate = Node::op(NodeKind::Difference,
                        {Node::leaf(Primitive::rectangle(30, 40, 44, 36)),
                         Node::leaf(Primitive::circle(30, 40, 9.3))});
  Node lens = Node::op(NodeKind::Intersection,
                       {Node::leaf(Primitive::circle(70, 22, 15.2)),
                        Node::leaf(Primitive::rectangle(74, 24, 22, 30, 30))});
  Node rest = Node::op(NodeKind::Union,
                       {Node::leaf(Primitive::ellipse(70, 55, 17.5, 8.25, 35)),
                        Node::leaf(Primitive::triangle(48, 66, 26, 14.5, 10, 0.4))});
  return Node::op(NodeKind::Union, {std::move(plate), std::move(rest), std::move(lens)});
}

}  // namespace csgfit::testing
