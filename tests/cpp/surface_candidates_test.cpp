// A part's surface read as its primitives (seed/surface_candidates.h): the shared reading of
// range images and meshes, on exact samples of a block with a through hole.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "csgfit/model/voxel_grid.h"
#include "csgfit/seed/surface_candidates.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Points every `step` on a 40 x 30 x 12 block with a hole of radius 7 through it along z at
// (20, 15), each with its normal out of the part (into the hole on the hole's wall).
struct Samples {
  std::vector<Vec3> points, normals;
  void add(Vec3 p, Vec3 n) { points.push_back(p), normals.push_back(n); }
};

Samples holed_block(double step) {
  Samples s;
  auto in_hole = [](double x, double y) { return std::hypot(x - 20, y - 15) < 7; };
  for (double x = step / 2; x < 40; x += step)
    for (double y = step / 2; y < 30; y += step) {
      if (in_hole(x, y)) continue;
      s.add({x, y, 0}, {0, 0, -1});
      s.add({x, y, 12}, {0, 0, 1});
    }
  for (double z = step / 2; z < 12; z += step) {
    for (double x = step / 2; x < 40; x += step) s.add({x, 0, z}, {0, -1, 0}), s.add({x, 30, z}, {0, 1, 0});
    for (double y = step / 2; y < 30; y += step) s.add({0, y, z}, {-1, 0, 0}), s.add({40, y, z}, {1, 0, 0});
    for (double a = 0; a < 2 * kPi; a += step / 7) {
      const double c = std::cos(a), d = std::sin(a);
      s.add({20 + 7 * c, 15 + 7 * d, z}, {-c, -d, 0});
    }
  }
  return s;
}

TEST(ReadSurface, AHoledBlockIsAPositiveBlockAndANegativeCylinder) {
  const Samples s = holed_block(0.5);
  const SurfaceReading r = read_surface(s.points, s.normals, SurfaceDetectOptions{},
                                        PrimitiveSet3D::matchable(), 1);
  ASSERT_EQ(r.graph.nodes.size(), 2u);
  const SignedPrimitive* block = nullptr;
  const SignedPrimitive* hole = nullptr;
  for (const SignedPrimitive& n : r.graph.nodes)
    (n.primitive.kind == PrimitiveKind3D::Box ? block : hole) = &n;
  ASSERT_NE(block, nullptr);
  ASSERT_NE(hole, nullptr);
  EXPECT_TRUE(block->positive);
  EXPECT_FALSE(hole->positive);
  EXPECT_EQ(hole->primitive.kind, PrimitiveKind3D::Cylinder);
  EXPECT_NEAR(hole->primitive.dims[0], 7.0, 0.1);
  EXPECT_NEAR(hole->primitive.cx, 20.0, 0.1);
  EXPECT_NEAR(hole->primitive.cy, 15.0, 0.1);
  EXPECT_NEAR(block->primitive.volume(), 40.0 * 30 * 12, 0.03 * 40 * 30 * 12);
  // The block comes first (order 1), the hole is cut from it (order 2).
  const Node3D tree = precedence_tree(r.graph);
  ASSERT_EQ(tree.kind, NodeKind::Difference);
  EXPECT_EQ(tree.primitive_count(), 2u);
}

TEST(ReadSurface, KindsNotAllowedAreNotRead) {
  const Samples s = holed_block(0.5);
  PrimitiveSet3D boxes_only;
  boxes_only.add(PrimitiveKind3D::Box);
  const SurfaceReading r = read_surface(s.points, s.normals, SurfaceDetectOptions{}, boxes_only, 1);
  for (const SignedPrimitive& n : r.graph.nodes) EXPECT_EQ(n.primitive.kind, PrimitiveKind3D::Box);
}

// A hexagonal hole is not the round hole of its circumradius, nor the hexagon turned by 30
// degrees: a pool keeps all three.
TEST(AddDistinct, KeepsPolygonsApartFromCirclesAndByTheirPhase) {
  const SignedPrimitive round{Primitive3D::cylinder(0, 0, 0, 3, 10), false};
  SignedPrimitive hex = round;
  hex.primitive.sides = 6;
  SignedPrimitive turned = hex;
  turned.primitive.rotation = Quaternion::from_axis_angle(0, 0, 1, 30);
  EXPECT_TRUE(alike(hex, hex, 0.1));
  EXPECT_FALSE(alike(round, hex, 0.1));
  EXPECT_FALSE(alike(hex, turned, 0.1));
  std::vector<SignedPrimitive> pool{round};
  add_distinct(pool, {hex, turned, hex}, 10);
  EXPECT_EQ(pool.size(), 3u);
}

TEST(OrientOutwards, FlipsTheNormalsThatPointIntoTheSolid) {
  // The block as voxels of 1, and every third normal turned inwards.
  VoxelGrid solid(44, 34, 16, -2, -2, -2, 1.0);
  for (int k = 2; k < 14; ++k)
    for (int j = 2; j < 32; ++j)
      for (int i = 2; i < 42; ++i)
        if (std::hypot(i - 2 + 0.5 - 20, j - 2 + 0.5 - 15) >= 7) solid.set(i, j, k);
  Samples s = holed_block(1.0);
  std::vector<Vec3> normals = s.normals;
  for (std::size_t i = 0; i < normals.size(); i += 3)
    for (double& c : normals[i]) c = -c;
  orient_outwards(normals, s.points, solid);
  // A right normal is never turned; a wrong one is, unless the voxels cannot tell (at the rim
  // of the hole, where 1.5 voxels behind a face may be empty too).
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    if (i % 3 != 0) EXPECT_EQ(normals[i], s.normals[i]) << i;
    wrong += normals[i] != s.normals[i];
  }
  EXPECT_LE(wrong, normals.size() / 100);
}

}  // namespace
}  // namespace csgfit
