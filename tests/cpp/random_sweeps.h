// Random 3D trees that are sweeps by construction (find_sweeps, the .scad and FreeCAD writers'
// extrusions and revolutions): prisms along one axis spanning one extent, or solids round
// about one line, under random operators, in a random frame.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "csgfit/model/tree3d.h"

namespace csgfit::testing {

/// The seed of a randomised test: CSGFIT_TEST_SEED when set (to replay a failure), else a new
/// one every run; the test prints it.
inline std::uint64_t test_seed() {
  const char* env = std::getenv("CSGFIT_TEST_SEED");
  if (env && *env) return std::strtoull(env, nullptr, 10);
  return (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
}

/// A sweep's frame: a model axis either way (half the time), else any rotation.
inline Quaternion random_sweep_frame(std::mt19937_64& rng) {
  static const double axes[6][3] = {{0, 0, 0},  {180, 0, 0}, {90, 0, 0},
                                    {-90, 0, 0}, {0, 90, 0},  {0, -90, 0}};
  if (rng() % 2) {
    const double* a = axes[rng() % 6];
    return Quaternion::from_euler_deg(a[0], a[1], a[2]);
  }
  std::normal_distribution<double> g(0, 1);
  Quaternion q{g(rng), g(rng), g(rng), g(rng)};
  q.normalize();
  return q;
}

/// Places a leaf given in the frame (centre `local`, its local z along the frame's z) at
/// centre + frame * local, turned about the axis by a random angle and upside down half the
/// time; `to_axis` first takes the leaf's own axis to its local z.
inline void place_in_frame(std::mt19937_64& rng, Primitive3D& p, const Vec3& centre,
                           const Quaternion& frame, const Vec3& local,
                           const Quaternion& to_axis = {}) {
  std::uniform_real_distribution<double> turn(-180, 180);
  const Quaternion flip = rng() % 2 ? Quaternion::from_euler_deg(180, 0, 0) : Quaternion{};
  p.rotation = frame * Quaternion::from_euler_deg(0, 0, turn(rng)) * flip * to_axis;
  const Mat3 m = frame.matrix();
  p.cx = centre[0] + m[0][0] * local[0] + m[0][1] * local[1] + m[0][2] * local[2];
  p.cy = centre[1] + m[1][0] * local[0] + m[1][1] * local[1] + m[1][2] * local[2];
  p.cz = centre[2] + m[2][0] * local[0] + m[2][1] * local[1] + m[2][2] * local[2];
  p.normalize();
}

/// Where a random sweep's leaves go: around `centre`, `spread` across the axis, sizes up to
/// `size`, a linear sweep `height` long.
struct SweepRegion {
  Vec3 centre{16, 16, 16};
  Quaternion frame;
  double spread = 5, size = 8, height = 9;
};

/// A prism along the frame's z spanning [-height/2, height/2] (a subtracted one may reach
/// beyond): a box along any of its own axes, a round or polygonal cylinder, a triangular prism
/// or a rounded box (a stadium one time in five).
inline Primitive3D random_prism_leaf(std::mt19937_64& rng, const SweepRegion& r, bool subtracted) {
  std::uniform_real_distribution<double> across(-r.spread, r.spread), dim(r.size / 4, r.size),
      apex(-1.2, 1.2), beyond(0.5, 3), unit(0, 1);
  double lo = -r.height / 2, hi = r.height / 2;
  if (subtracted && rng() % 2) lo -= beyond(rng), hi += beyond(rng);
  const Vec3 local{across(rng), across(rng), (lo + hi) / 2};
  const double length = hi - lo;
  Primitive3D p;
  Quaternion to_axis;
  switch (rng() % 5) {
    case 0: {
      const int axis = static_cast<int>(rng() % 3);
      static const double takes_to_z[3][3] = {{0, -90, 0}, {90, 0, 0}, {0, 0, 0}};
      to_axis = Quaternion::from_euler_deg(takes_to_z[axis][0], takes_to_z[axis][1], 0);
      Vec3 dims{dim(rng), dim(rng), dim(rng)};
      dims[static_cast<std::size_t>(axis)] = length;
      p = Primitive3D::box(0, 0, 0, dims[0], dims[1], dims[2]);
      break;
    }
    case 1: p = Primitive3D::cylinder(0, 0, 0, dim(rng) / 2, length); break;
    case 2:
      p = Primitive3D::cylinder(0, 0, 0, dim(rng) / 2, length);
      p.sides = 3 + static_cast<int>(rng() % 6);
      break;
    case 3: p = Primitive3D::prism(0, 0, 0, dim(rng), dim(rng), length, apex(rng)); break;
    default: {
      const double sx = dim(rng), sy = dim(rng), u = unit(rng);
      const double corner = std::min(sx, sy) / 2 * (u < 0.2 ? 1 : 0.1 + 0.8 * u);
      p = Primitive3D::rounded_box(0, 0, 0, sx, sy, length, corner);
      break;
    }
  }
  place_in_frame(rng, p, r.centre, r.frame, local, to_axis);
  return p;
}

/// A solid round about the frame's z axis through the centre: a cylinder or cone (pointed or
/// not) anywhere along it, a torus, or a sphere centred on it.
inline Primitive3D random_round_leaf(std::mt19937_64& rng, const SweepRegion& r) {
  std::uniform_real_distribution<double> along(-r.spread, r.spread), dim(r.size / 4, r.size),
      unit(0, 1);
  const Vec3 local{0, 0, along(rng)};
  Primitive3D p;
  switch (rng() % 4) {
    case 0: p = Primitive3D::cylinder(0, 0, 0, dim(rng) / 2, dim(rng)); break;
    case 1: {
      const double r2 = unit(rng) < 0.3 ? 0 : dim(rng) / 3;
      p = Primitive3D::cone(0, 0, 0, dim(rng) / 2, r2, dim(rng));
      break;
    }
    case 2: {
      const double major = dim(rng) / 2;
      p = Primitive3D::torus(0, 0, 0, major, major * (0.25 + 0.6 * unit(rng)));
      break;
    }
    default: p = Primitive3D::sphere(0, 0, 0, dim(rng) / 2); break;
  }
  place_in_frame(rng, p, r.centre, r.frame, local);
  return p;
}

/// A random tree of up to `depth` operator levels over leaves from make_leaf(rng, subtracted).
template <typename MakeLeaf>
Node3D random_sweep_tree(std::mt19937_64& rng, int depth, bool subtracted, const MakeLeaf& make_leaf) {
  if (depth <= 0 || rng() % 3 == 0) return Node3D::leaf(make_leaf(rng, subtracted));
  static const NodeKind ops[4] = {NodeKind::Union, NodeKind::Union, NodeKind::Difference,
                                  NodeKind::Intersection};
  const NodeKind op = ops[rng() % 4];
  std::vector<Node3D> children;
  const int n = 2 + static_cast<int>(rng() % 2);
  for (int i = 0; i < n; ++i) {
    const bool cut = op == NodeKind::Difference && i > 0;
    children.push_back(random_sweep_tree(rng, depth - 1, subtracted != cut, make_leaf));
  }
  return Node3D::op(op, std::move(children));
}

/// A random tree that is one linear sweep along the region's frame z: at least two leaves.
inline Node3D random_linear_tree(std::mt19937_64& rng, const SweepRegion& r, int depth = 2) {
  auto leaf = [&r](std::mt19937_64& g, bool subtracted) { return random_prism_leaf(g, r, subtracted); };
  Node3D t;
  do t = random_sweep_tree(rng, depth, false, leaf);
  while (t.primitive_count() < 2);
  return t;
}

/// A random tree that is one revolution about the region's frame z: at least two leaves, one
/// of them a torus, so that it is no linear sweep too.
inline Node3D random_revolution_tree(std::mt19937_64& rng, const SweepRegion& r, int depth = 2) {
  auto leaf = [&r](std::mt19937_64& g, bool) { return random_round_leaf(g, r); };
  std::uniform_real_distribution<double> along(-r.spread, r.spread), dim(r.size / 4, r.size);
  const double major = dim(rng) / 2;
  Primitive3D torus = Primitive3D::torus(0, 0, 0, major, major * 0.5);
  place_in_frame(rng, torus, r.centre, r.frame, {0, 0, along(rng)});
  return Node3D::op(NodeKind::Union,
                    {random_sweep_tree(rng, depth, false, leaf), Node3D::leaf(torus)});
}

}  // namespace csgfit::testing
