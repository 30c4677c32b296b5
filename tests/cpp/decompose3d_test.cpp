// Seed 003 in 3D: connected regions and moments, the moment matcher on exact voxelised
// primitives, and the recursive box decomposition.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "csgfit/seed/decompose3d.h"
#include "csgfit/features/features3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/quaternion.h"

using namespace csgfit;

namespace {

VoxelGrid grid(int n = 48) { return VoxelGrid(n, n, n, 0, 0, 0, 1.0); }

VoxelGrid raster(const Primitive3D& p, int n = 48) {
  VoxelGrid g = grid(n);
  rasterize(p, g);
  return g;
}

// The three dimensions of `p`, in whatever order the matcher gave them, are the sorted `want`.
void expect_dims_near(const Primitive3D& p, std::vector<double> want, double tolerance) {
  std::vector<double> got(p.dims.begin(), p.dims.end());
  std::sort(got.begin(), got.end());
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tolerance) << "dimension " << i;
}

// The matcher's primitive for the raster of `p`, which must be of `kind` (a default primitive
// when nothing matched, after the failure).
Primitive3D match_of(const Primitive3D& p, PrimitiveKind3D kind) {
  const auto m = match_region3d(raster(p), PrimitiveSet3D::matchable());
  EXPECT_TRUE(m.has_value()) << to_string(kind);
  if (!m) return {};
  EXPECT_EQ(m->primitive.kind, kind) << to_string(m->primitive.kind);
  return m->primitive;
}

std::vector<double> sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

TEST(Features3D, ConnectivityOfCornerNeighbours) {
  VoxelGrid g = grid(8);
  g.set(2, 2, 2);
  g.set(3, 3, 3);  // shares only a corner
  g.set(5, 5, 2);
  g.set(6, 5, 3);  // shares only an edge
  EXPECT_EQ(connected_regions3d(g, 6).size(), 4u);
  EXPECT_EQ(connected_regions3d(g, 18).size(), 3u);
  EXPECT_EQ(connected_regions3d(g, 26).size(), 2u);
  EXPECT_EQ(dual_connectivity(6), 26);
  EXPECT_THROW(connected_regions3d(g, 7), std::invalid_argument);
}

TEST(Features3D, RegionsAreCroppedInModelCoordinates) {
  VoxelGrid g(20, 20, 20, -5, 1, 2, 0.5);
  rasterize(Primitive3D::box(0.1, 4.1, 5.1, 2, 3, 1.5), g);
  const auto regs = connected_regions3d(g, 6);
  ASSERT_EQ(regs.size(), 1u);
  const Region3D& r = regs[0];
  EXPECT_EQ(r.volume, g.count());
  EXPECT_EQ(r.mask.count(), g.count());
  EXPECT_EQ(r.mask.nx(), r.hi[0] - r.lo[0] + 1);
  EXPECT_DOUBLE_EQ(r.mask.origin_x(), -5 + r.lo[0] * 0.5);
  EXPECT_EQ(r.mask.count(), r.mask.nx() * static_cast<std::size_t>(r.mask.ny()) * r.mask.nz());
}

TEST(Features3D, MomentsOfABox) {
  VoxelGrid g = grid(32);
  rasterize(Primitive3D::box(16, 16, 16, 20, 10, 6), g);
  const Moments3D m = compute_moments3d(g);
  EXPECT_NEAR(m.volume, 1200, 1e-9);
  EXPECT_NEAR(m.centroid[0], 16, 1e-9);
  // The +1/12 voxel term makes a voxelised box's variances exact: size^2 / 12.
  EXPECT_NEAR(m.variances[0], 400.0 / 12, 1e-9);
  EXPECT_NEAR(m.variances[1], 100.0 / 12, 1e-9);
  EXPECT_NEAR(m.variances[2], 36.0 / 12, 1e-9);
  EXPECT_NEAR(std::fabs(m.axes[0][0]), 1, 1e-9);
}

TEST(Features3D, JacobiEigenOfARotatedMatrix) {
  const Mat3 r = Quaternion::from_euler_deg(20, 35, -50).matrix();
  const double d[3] = {9, 4, 1};
  Mat3 a{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) a[i][j] += r[i][k] * d[k] * r[j][k];
  Vec3 vals;
  Mat3 vecs;
  symmetric_eigen3(a, vals, vecs);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(vals[i], d[i], 1e-10);
  for (int c = 0; c < 3; ++c) {
    const double dot = vecs[0][c] * r[0][c] + vecs[1][c] * r[1][c] + vecs[2][c] * r[2][c];
    EXPECT_NEAR(std::fabs(dot), 1, 1e-9);
  }
  const Quaternion q = quaternion_from_matrix(vecs);
  const Mat3 back = q.matrix();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(back[i][j], vecs[i][j], 1e-9);
}

TEST(Features3D, ErodeRemovesTheSkin) {
  VoxelGrid g = grid(16);
  rasterize(Primitive3D::box(8, 8, 8, 6, 6, 6), g);
  EXPECT_EQ(erode6(g).count(), 64u);
}

TEST(Matcher3D, RecognisesARotatedBox) {
  const Primitive3D p = Primitive3D::box(24.3, 23.7, 24.1, 24, 14, 8, Quaternion::from_euler_deg(20, 30, 10));
  auto m = match_region3d(raster(p), PrimitiveSet3D::matchable());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind3D::Box);
  expect_dims_near(m->primitive, {8, 14, 24}, 1.0);
  EXPECT_NEAR(m->block_volume_ratio, 1, 0.05);
}

TEST(Matcher3D, RecognisesASphere) {
  const Primitive3D got = match_of(Primitive3D::sphere(24.3, 23.7, 24.1, 11), PrimitiveKind3D::Sphere);
  EXPECT_NEAR(got.dims[0], 11, 0.5);
}

TEST(Matcher3D, RecognisesAnEllipsoid) {
  const Primitive3D p = Primitive3D::ellipsoid(24.3, 23.7, 24.1, 16, 10, 6, Quaternion::from_euler_deg(0, 40, 25));
  expect_dims_near(match_of(p, PrimitiveKind3D::Ellipsoid), {6, 10, 16}, 1.0);
}

TEST(Matcher3D, RecognisesACylinderAlongItsDistinctAxis) {
  for (double h : {30.0, 8.0}) {  // long and flat: the distinct moment is the largest or smallest
    const Primitive3D p = Primitive3D::cylinder(24.3, 23.7, 24.1, 9, h, Quaternion::from_euler_deg(35, -20, 0));
    const Primitive3D got = match_of(p, PrimitiveKind3D::Cylinder);
    EXPECT_NEAR(got.dims[0], 9, 1.0) << h;
    EXPECT_NEAR(got.dims[2], h, 1.0);
  }
}

TEST(Matcher3D, RecognisesAConeAndAFrustum) {
  for (double r2 : {0.0, 5.0}) {
    const Primitive3D p = Primitive3D::cone(24.3, 23.7, 24.1, 12, r2, 26, Quaternion::from_euler_deg(15, 25, 5));
    const Primitive3D got = match_of(p, PrimitiveKind3D::Cone);
    const auto radii = sorted({got.dims[0], got.dims[1]});
    EXPECT_NEAR(radii[0], r2, 1.0);
    EXPECT_NEAR(radii[1], 12, 1.0);
    EXPECT_NEAR(got.dims[2], 26, 1.0);
  }
}

TEST(Matcher3D, RecognisesATriangularBlock) {
  const Primitive3D p = Primitive3D::prism(24.3, 23.7, 24.1, 26, 18, 14, 0, Quaternion::from_euler_deg(10, 0, 30));
  auto m = match_region3d(raster(p), PrimitiveSet3D::matchable());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind3D::TriangularPrism);
  EXPECT_NEAR(m->primitive.dims[0], 26, 1.0);
  EXPECT_NEAR(m->primitive.dims[1], 18, 1.0);
  EXPECT_NEAR(m->primitive.dims[2], 14, 1.0);
  const double vol = static_cast<double>(raster(p).count());
  EXPECT_LT(static_cast<double>(m->mismatch), 0.03 * vol);
}

TEST(Matcher3D, HonoursTheAllowedKinds) {
  PrimitiveSet3D only_box;
  only_box.add(PrimitiveKind3D::Box);
  auto m = match_region3d(raster(Primitive3D::sphere(24.3, 23.7, 24.1, 10)), only_box);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind3D::Box);
  EXPECT_FALSE(match_region3d(grid(8), PrimitiveSet3D::matchable()));
  EXPECT_FALSE(match_region3d(raster(Primitive3D::sphere(24, 24, 24, 5)), PrimitiveSet3D{}));
}

TEST(Decompose3D, BoxWithACylindricalHoleIsTwoPrimitives) {
  const Node3D truth = Node3D::op(
      NodeKind::Difference, {Node3D::leaf(Primitive3D::box(24, 24, 24, 36, 28, 16)),
                             Node3D::leaf(Primitive3D::cylinder(22.3, 25.1, 24, 7, 16))});
  const VoxelGrid target = render(truth, grid());
  DecomposeOptions3D opt;
  opt.k = 50;
  const Node3D tree = decompose3d(target, opt);
  EXPECT_EQ(tree.primitive_count(), 2u) << structure_string(tree);
  EXPECT_EQ(structure_string(tree), "difference(box, cylinder)");
  EXPECT_GT(iou(render(tree, target), target), 0.98);
}

TEST(Decompose3D, LShapedBlock) {
  const Node3D truth = Node3D::op(
      NodeKind::Union, {Node3D::leaf(Primitive3D::box(20, 24, 24, 24, 10, 20)),
                        Node3D::leaf(Primitive3D::box(13, 32, 24, 10, 20, 20))});
  const VoxelGrid target = render(truth, grid());
  DecomposeOptions3D opt;
  opt.k = 50;
  const Node3D tree = decompose3d(target, opt);
  EXPECT_EQ(tree.primitive_count(), 2u) << structure_string(tree);
  EXPECT_DOUBLE_EQ(iou(render(tree, target), target), 1.0);
}

TEST(Decompose3D, TetrahedronInItsBoxTerminates) {
  // Seed 003's Figure 15: the complement of a tetrahedron with its vertices on the box's faces
  // spans the whole box.
  VoxelGrid target = grid(24);
  for (int k = 0; k < 24; ++k)
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const double x = (i + 0.5) / 24, y = (j + 0.5) / 24, z = (k + 0.5) / 24;
        if (x + y + z <= 1.0) target.set(i, j, k);
      }
  DecomposeOptions3D opt;
  opt.k = 5;
  const Node3D tree = decompose3d(target, opt);
  EXPECT_GE(tree.primitive_count(), 1u);
  EXPECT_GT(iou(render(tree, target), target), 0.7);
}

TEST(Decompose3D, AlwaysTerminatesOnRandomVoxels) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    VoxelGrid target = grid(16);
    const double density = 0.2 + 0.2 * trial;
    for (int k = 0; k < 16; ++k)
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i)
          if (std::uniform_real_distribution<double>(0, 1)(rng) < density) target.set(i, j, k);
    DecomposeOptions3D opt;
    opt.k = trial == 0 ? 0 : 3;
    const Node3D tree = decompose3d(target, opt);
    EXPECT_GE(tree.primitive_count(), 1u);
    EXPECT_GT(iou(render(tree, target), target), 0.0);
  }
}

TEST(Decompose3D, RejectsEmptyTargets) {
  EXPECT_THROW(decompose3d(grid(8), DecomposeOptions3D{}), std::invalid_argument);
}
