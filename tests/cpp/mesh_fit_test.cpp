// The mesh-to-tree steps around the voxel search: the fitting frame, the least-squares
// refinement against surface samples, the snaps, and a whole fit of a turned part.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/features/mesh_features.h"
#include "csgfit/optimise/snap3d.h"
#include "csgfit/refine/surface_fit3d.h"

namespace csgfit {
namespace {

// Box [lo, hi] as 12 outward triangles, turned by q about the origin.
TriangleMesh turned_box(std::array<double, 3> lo, std::array<double, 3> hi, const Quaternion& q = {}) {
  static const int kTriangles[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                        {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                        {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const Mat3 m = q.matrix();
  TriangleMesh mesh;
  for (int v = 0; v < 8; ++v) {
    const double p[3] = {(v & 1) ? hi[0] : lo[0], (v & 2) ? hi[1] : lo[1], (v & 4) ? hi[2] : lo[2]};
    mesh.vertices.push_back({m[0][0] * p[0] + m[0][1] * p[1] + m[0][2] * p[2],
                             m[1][0] * p[0] + m[1][1] * p[1] + m[1][2] * p[2],
                             m[2][0] * p[0] + m[2][1] * p[1] + m[2][2] * p[2]});
  }
  for (const auto& t : kTriangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  return mesh;
}

// Angle in degrees between two rotations' local axes, ignoring which axis is which: the
// largest angle between a column of a and its best-matching signed column of b.
double frame_difference_deg(const Quaternion& a, const Quaternion& b) {
  const Mat3 ma = a.matrix(), mb = b.matrix();
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    double best = 0;
    for (int j = 0; j < 3; ++j) {
      double c = 0;
      for (int r = 0; r < 3; ++r) c += ma[r][i] * mb[r][j];
      best = std::max(best, std::fabs(c));
    }
    worst = std::max(worst, std::acos(std::min(1.0, best)) * 180 / 3.14159265358979323846);
  }
  return worst;
}

TEST(DominantFrame, AxisAlignedPartsKeepTheirAxes) {
  EXPECT_TRUE(dominant_frame(turned_box({0, 0, 0}, {4, 2, 1})).is_identity());
}

TEST(DominantFrame, FindsTheFacesOfATurnedPart) {
  const Quaternion q = Quaternion::from_euler_deg(2, 4, 25);
  const Quaternion f = dominant_frame(turned_box({0, 0, 0}, {4, 2, 1}, q));
  EXPECT_FALSE(f.is_identity());
  EXPECT_LT(frame_difference_deg(f, q), 0.01);
}

TEST(RefineToSurface, MovesPrimitivesBetweenVoxelCentres) {
  // A box whose faces lie 0.3 voxel off the voxel centres: the voxels cannot tell it from a
  // box 0.3 voxel smaller, the surface samples can.
  const VoxelGrid frame(24, 24, 24, 0, 0, 0, 1.0);
  const Primitive3D truth = Primitive3D::box(12.1, 11.9, 12.0, 10.6, 8.6, 9.4);
  VoxelGrid target = frame;
  rasterize(truth, target);
  Node3D tree = Node3D::leaf(Primitive3D::box(12.0, 12.0, 12.0, 10.0, 8.0, 9.0));
  TreeEvaluator3D ev(target, tree);
  const std::size_t before = ev.mismatch().total();
  const TriangleMesh mesh = turned_box({12.1 - 5.3, 11.9 - 4.3, 12.0 - 4.7}, {12.1 + 5.3, 11.9 + 4.3, 12.0 + 4.7});
  EXPECT_EQ(refine_to_surface(ev, surface_samples(mesh, 4000, 1)), 1u);
  EXPECT_LE(ev.mismatch().total(), before);
  const Primitive3D& p = ev.leaf(0);
  EXPECT_NEAR(p.cx, truth.cx, 0.02);
  EXPECT_NEAR(p.cy, truth.cy, 0.02);
  EXPECT_NEAR(p.cz, truth.cz, 0.02);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(p.dims[a], truth.dims[a], 0.04) << a;
  EXPECT_TRUE(p.rotation.is_identity(1e-6) || frame_difference_deg(p.rotation, {}) < 0.05);
}

// Sum over the samples of the tree's squared signed distance, capped as refine_to_surface caps it.
double capped_residual(const Node3D& tree, const std::vector<Vec3>& samples, double cap) {
  double sum = 0;
  for (const Vec3& s : samples) {
    const double d = std::min(std::fabs(signed_distance(tree, s[0], s[1], s[2])), cap);
    sum += d * d;
  }
  return sum;
}

TEST(RefineToSurface, NeverLeavesTheTreesSurfaceFurtherFromTheSamples) {
  // An L-shaped part (a slab and a block on it) and trees of four boxes fitted to it roughly,
  // with a fifth cutting (nearly) nothing above it, in random placements and slight turns
  // (fixed seed). Samples go to the primitive that makes the tree's surface where they are,
  // which its refinement may carry off that surface; whatever the refinement keeps, the tree's surface as a whole
  // must end no further from the samples than it began, and mostly much nearer.
  const VoxelGrid frame(40, 30, 30, 0, 0, 0, 1.0);
  VoxelGrid target = frame;
  rasterize(Primitive3D::box(20, 15, 8, 30, 20, 6), target);    // slab, z 5 .. 11
  rasterize(Primitive3D::box(12, 15, 16, 10, 20, 10), target);  // block, z 11 .. 21
  TriangleMesh mesh = turned_box({5, 5, 5}, {35, 25, 11});
  const TriangleMesh upper = turned_box({7, 5, 11}, {17, 25, 21});
  for (const auto& t : upper.triangles) mesh.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  mesh.vertices.insert(mesh.vertices.end(), upper.vertices.begin(), upper.vertices.end());
  const std::vector<Vec3> samples = surface_samples(mesh, 4000, 3);
  std::uint64_t state = 12345;
  auto jitter = [&](double amplitude) {  // deterministic, uniform in [-amplitude, amplitude]
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return amplitude * (static_cast<double>(state >> 11) / 9007199254740992.0 * 2 - 1);
  };
  int improved = 0;
  for (int trial = 0; trial < 12; ++trial) {
    auto turn = [&] { return Quaternion::from_euler_deg(jitter(3), jitter(3), jitter(3)); };
    std::vector<Node3D> parts{
        Node3D::leaf(Primitive3D::box(20 + jitter(0.6), 15, 8 + jitter(0.6), 30, 20, 6 + jitter(0.8), turn())),
        Node3D::leaf(Primitive3D::box(12 + jitter(0.6), 15, 16 + jitter(0.6), 10, 20, 10 + jitter(0.8), turn())),
        Node3D::leaf(Primitive3D::box(24 + jitter(3), 15 + jitter(3), 9.5 + jitter(1), 6, 8, 2.6, turn())),
        Node3D::leaf(Primitive3D::box(14 + jitter(1), 15, 19 + jitter(1), 6, 24, 4, turn()))};
    Node3D tree = Node3D::op(
        NodeKind::Difference,
        {Node3D::op(NodeKind::Union, parts),
         Node3D::leaf(Primitive3D::box(27 + jitter(2), 15 + jitter(2), 12.2 + jitter(0.5), 6, 6, 2, turn()))});
    const double cap = 1.5;
    const double before = capped_residual(tree, samples, cap);
    TreeEvaluator3D ev(target, tree);
    SurfaceFitOptions3D options;
    options.voxel_slack = 1e9;  // only the surface decides
    refine_to_surface(ev, samples, options);
    const double after = capped_residual(tree, samples, cap);
    EXPECT_LE(after, before * (1 + 1e-12)) << "trial " << trial;
    improved += after < 0.9 * before;
  }
  EXPECT_GE(improved, 8);
}

TEST(RefineToSurface, MovesThePrimitiveThatSticksOutNotTheOneHiddenUnderIt) {
  // A block fitted as two boxes: one exactly, and one over part of it that sticks out 0.4
  // voxel past the +x face, between two rows of centres. The exact box's face is nearer to the
  // samples on that face, but the box that sticks out makes the tree's surface there: it takes
  // those samples and its face comes back onto them.
  const VoxelGrid frame(24, 24, 24, 0, 0, 0, 1.0);
  VoxelGrid target = frame;
  rasterize(Primitive3D::box(10, 10, 10, 12, 12, 12), target);  // x, y, z in [4, 16]
  Node3D tree = Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(10, 10, 10, 12, 12, 12)),
                                             Node3D::leaf(Primitive3D::box(12.2, 10, 10, 8.4, 12, 12))});
  TreeEvaluator3D ev(target, tree);
  ASSERT_EQ(ev.mismatch().total(), 0u);  // the voxels cannot see it
  EXPECT_EQ(ev.surface_leaf(16, 10, 10), 1u);
  EXPECT_EQ(ev.surface_leaf(4, 10, 10), 0u);
  refine_to_surface(ev, surface_samples(turned_box({4, 4, 4}, {16, 16, 16}), 4000, 5));
  const Primitive3D& out = ev.leaf(1);
  EXPECT_NEAR(out.cx + 0.5 * out.dims[0], 16.0, 0.05);
  EXPECT_EQ(ev.leaf(0), Primitive3D::box(10, 10, 10, 12, 12, 12));
  EXPECT_EQ(ev.mismatch().total(), 0u);
}

TEST(SnapToDesignValues, SquaresUpNearlyAlignedPrimitivesAndEqualisesRadii) {
  const VoxelGrid frame(40, 40, 40, 0, 0, 0, 1.0);
  VoxelGrid target = frame;
  rasterize(Primitive3D::box(20, 20, 20, 16, 12, 10), target);
  Node3D tree = Node3D::op(NodeKind::Difference,
                           {Node3D::leaf(Primitive3D::box(20, 20, 20, 16, 12, 10,
                                                          Quaternion::from_euler_deg(1, -1.5, 2))),
                            Node3D::leaf(Primitive3D::cylinder(14, 20, 20, 2.0, 12)),
                            Node3D::leaf(Primitive3D::cylinder(26, 20, 20, 2.03, 12,
                                                               Quaternion::from_euler_deg(0, 3, 0)))});
  TreeEvaluator3D ev(target, tree);
  EXPECT_GE(snap_to_design_values(ev, 1e9), 3u);
  EXPECT_TRUE(ev.leaf(0).rotation.is_identity(1e-9));
  EXPECT_TRUE(ev.leaf(2).rotation.is_identity(1e-9));
  EXPECT_EQ(ev.leaf(2).dims[0], ev.leaf(1).dims[0]);
  // With no slack a snap that costs voxels is refused.
  Node3D costly = Node3D::leaf(Primitive3D::box(20, 20, 20, 30, 4, 4, Quaternion::from_euler_deg(0, 0, 3)));
  TreeEvaluator3D ev2(target, costly);
  const std::size_t before = ev2.mismatch().total();
  snap_to_design_values(ev2, 0);
  EXPECT_LE(ev2.mismatch().total(), before);
}

// A hex prism's turn about its axis is its phase: squaring up its axis keeps it (30 degrees:
// flats towards x), a turn of 22 degrees stays 22, and 61 is the same hexagon as 1 and becomes
// 0. Its circumradius is not made equal to a round hole's radius.
TEST(SnapToDesignValues, KeepsAPolygonsPhaseAndItsOwnRadius) {
  const VoxelGrid frame(40, 40, 40, 0, 0, 0, 1.0);
  const VoxelGrid target = frame;
  auto hex = [](double x, double r, const Quaternion& q) {
    Primitive3D p = Primitive3D::cylinder(x, 20, 20, r, 12, q);
    p.sides = 6;
    return p;
  };
  const Quaternion tilt = Quaternion::from_euler_deg(1.5, 0, 0);
  auto turn = [](double degrees) { return Quaternion::from_axis_angle(0, 0, 1, degrees); };
  Node3D tree = Node3D::op(
      NodeKind::Union, {Node3D::leaf(Primitive3D::cylinder(6, 20, 20, 2.0, 12)),
                        Node3D::leaf(hex(14, 2.03, tilt * turn(30))),
                        Node3D::leaf(hex(22, 3, tilt * turn(22))),
                        Node3D::leaf(hex(30, 3, turn(61)))});
  TreeEvaluator3D ev(target, tree);
  snap_to_design_values(ev, 1e9);
  auto expect_turn = [&](std::size_t leaf, double degrees) {
    const Mat3 got = ev.leaf(leaf).rotation.matrix();
    const Mat3 want = Quaternion::from_axis_angle(0, 0, 1, degrees).matrix();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(got[i][j], want[i][j], 2e-3) << "leaf " << leaf;
  };
  expect_turn(1, 30);
  expect_turn(2, 22);
  expect_turn(3, 0);
  EXPECT_EQ(ev.leaf(1).dims[0], 2.03);
  EXPECT_EQ(ev.leaf(1).sides, 6);
}

// A boss with a bore through it, fitted with the bore 0.3 voxel off the boss's axis: the bore
// becomes coaxial with the boss; a second hole 3 voxels away stays where it is.
TEST(SnapToDesignValues, MakesNearlyCoaxialCylindersCoaxial) {
  const VoxelGrid frame(40, 40, 40, 0, 0, 0, 1.0);
  const Node3D truth = Node3D::op(
      NodeKind::Difference,
      {Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(20, 20, 12, 30, 30, 6)),
                                    Node3D::leaf(Primitive3D::cylinder(20.2, 19.9, 18, 6, 12))}),
       Node3D::leaf(Primitive3D::cylinder(20.2, 19.9, 18, 3, 30)),
       Node3D::leaf(Primitive3D::cylinder(11.1, 19.9, 12, 2, 10))});
  const VoxelGrid target = render(truth, frame);
  Node3D tree = truth;
  std::vector<Primitive3D*> ls = leaves(tree);
  ls[2]->cx += 0.3;  // the bore, off the boss's axis
  ls[2]->cy -= 0.1;
  ls[3]->cx = 17.1;  // another hole, 3 voxels from the boss's axis
  TreeEvaluator3D ev(target, tree);
  snap_to_design_values(ev, 1e9);
  EXPECT_NEAR(ev.leaf(2).cx, ev.leaf(1).cx, 1e-12);
  EXPECT_NEAR(ev.leaf(2).cy, ev.leaf(1).cy, 1e-12);
  EXPECT_EQ(ev.leaf(2).cz, 18.0);  // kept its place along the axis
  EXPECT_EQ(ev.leaf(3).cx, 17.1);
  // Under no slack the snap is kept only if it costs nothing: the mismatch never grows.
  Node3D again = truth;
  leaves(again)[2]->cx += 0.45;
  TreeEvaluator3D ev2(target, again);
  const std::size_t before = ev2.mismatch().total();
  snap_to_design_values(ev2, 0);
  EXPECT_LE(ev2.mismatch().total(), before);
}

TEST(AxisPlanes, AreTheFacesOfAnAxisAlignedPartWithTheirAreas) {
  const TriangleMesh box = turned_box({0, 0, 0}, {4, 2, 1});
  const std::vector<AxisPlane> planes = axis_planes(box, 1e-6, 0);
  ASSERT_EQ(planes.size(), 6u);
  const double expected[3][2] = {{0, 4}, {0, 2}, {0, 1}};
  const double area[3] = {2, 4, 8};
  for (const AxisPlane& pl : planes) {
    EXPECT_TRUE(pl.offset == expected[pl.axis][0] || pl.offset == expected[pl.axis][1]) << pl.offset;
    EXPECT_NEAR(pl.area, area[pl.axis], 1e-12);
  }
  // Faces below the minimum area are dropped; a turned part has no axis planes at all.
  EXPECT_EQ(axis_planes(box, 1e-6, 3).size(), 4u);
  EXPECT_TRUE(axis_planes(turned_box({0, 0, 0}, {4, 2, 1}, Quaternion::from_euler_deg(0, 0, 10)), 1e-6, 0)
                  .size() == 2u);  // only the top and bottom stay perpendicular to z
}

TEST(SnapToPlanes, PutsFacesOnTheInputsPlanesAndMakesSharedFacesCoplanar) {
  // Two boxes whose tops should both be the part's top at z = 10.3 but sit a few hundredths
  // of a voxel apart, and whose outer faces are off by a fraction of a voxel: the voxels cannot
  // see any of it, the planes can.
  const VoxelGrid frame(30, 20, 20, 0, 0, 0, 1.0);
  VoxelGrid target = frame;
  const Primitive3D a = Primitive3D::box(8.0, 10.0, 6.15, 12.0, 10.0, 8.3);   // z 2.0 .. 10.3
  const Primitive3D b = Primitive3D::box(20.0, 10.0, 6.15, 12.0, 10.0, 8.3);
  rasterize(a, target);
  rasterize(b, target);
  const TriangleMesh mesh = turned_box({2.0, 5.0, 2.0}, {26.0, 15.0, 10.3});
  Node3D tree = Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(8.1, 10.0, 6.2, 12.0, 10.2, 8.3)),
                                             Node3D::leaf(Primitive3D::box(19.9, 10.0, 6.14, 12.0, 10.0, 8.3))});
  TreeEvaluator3D ev(target, tree);
  const std::size_t before = ev.mismatch().total();
  EXPECT_GE(snap_to_planes(ev, axis_planes(mesh, 1e-6, 1), 0.4, 0), 5u);
  EXPECT_LE(ev.mismatch().total(), before);
  for (std::size_t i = 0; i < 2; ++i) {
    const Primitive3D& p = ev.leaf(i);
    EXPECT_NEAR(p.cz + 0.5 * p.dims[2], 10.3, 1e-12) << i;  // both tops on the plane
    EXPECT_NEAR(p.cz - 0.5 * p.dims[2], 2.0, 1e-12) << i;
    EXPECT_NEAR(p.cy - 0.5 * p.dims[1], 5.0, 1e-12) << i;
    EXPECT_NEAR(p.cy + 0.5 * p.dims[1], 15.0, 1e-12) << i;
  }
  EXPECT_NEAR(ev.leaf(0).cx - 0.5 * ev.leaf(0).dims[0], 2.0, 1e-12);
  EXPECT_NEAR(ev.leaf(1).cx + 0.5 * ev.leaf(1).dims[0], 26.0, 1e-12);
  // The inner faces (x = 14.1 and 13.9) have no plane within reach and stay.
  EXPECT_NEAR(ev.leaf(0).cx + 0.5 * ev.leaf(0).dims[0], 14.1, 1e-12);
  // Nothing within the tolerance, nothing moves.
  Node3D far = Node3D::leaf(Primitive3D::box(8.0, 10.0, 5.0, 8.0, 6.0, 2.0));
  TreeEvaluator3D ev2(target, far);
  EXPECT_EQ(snap_to_planes(ev2, axis_planes(mesh, 1e-6, 1), 0.4, 1e9), 0u);
}

TEST(SnapToPlanes, ACutTurnedByAHairStillMeetsThePlane) {
  // A plate minus a pocket whose box is turned by 0.006 degree (as the surface fit leaves it)
  // and whose top lies 0.03 below the plate's: a skin OpenSCAD renders and no voxel centre
  // sees. The pocket's top goes onto the plane; a box turned by 2 degrees is not touched.
  const VoxelGrid frame(30, 20, 20, 0, 0, 0, 1.0);
  const Node3D truth = Node3D::op(NodeKind::Difference,
                                  {Node3D::leaf(Primitive3D::box(14, 10, 6, 20, 12, 8)),     // z 2 .. 10
                                   Node3D::leaf(Primitive3D::box(14, 10, 8, 10, 6, 4))});    // z 6 .. 10
  const VoxelGrid target = render(truth, frame);
  const TriangleMesh top = turned_box({4, 4, 2}, {24, 16, 10});
  for (const double turn : {0.006, 2.0}) {
    Node3D tree = Node3D::op(
        NodeKind::Difference,
        {Node3D::leaf(Primitive3D::box(14, 10, 6, 20, 12, 8)),
         Node3D::leaf(Primitive3D::box(14, 10, 7.985, 10, 6, 3.97, Quaternion::from_euler_deg(turn, 0, 0)))});
    TreeEvaluator3D ev(target, tree);
    snap_to_planes(ev, axis_planes(top, 1e-6, 1), 0.4, 0);
    const Primitive3D& pocket = ev.leaf(1);
    const double pocket_top = pocket.cz + 0.5 * pocket.dims[2];
    if (turn < 0.5) EXPECT_NEAR(pocket_top, 10.0, 1e-3);
    else EXPECT_NEAR(pocket_top, 9.97, 1e-12);
  }
}

TEST(FitMesh, ATurnedBlockIsOneBoxInItsOwnFrame) {
  // The tests end by convergence, not the clock: the budget is generous for such a part.
  const Quaternion q = Quaternion::from_euler_deg(10, 20, 30);
  const TriangleMesh block = turned_box({0, 0, 0}, {32, 20, 12}, q);
  FitOptions3D options;
  options.time_limit = 60;
  options.threads = 1;
  options.search.max_stale = 200;
  const MeshFitResult r = fit_mesh(block, options);
  EXPECT_LT(frame_difference_deg(r.frame, q), 0.01);
  EXPECT_EQ(r.fit.tree.primitive_count(), 1u);
  ASSERT_TRUE(r.fit.tree.is_leaf());
  const Primitive3D& p = r.fit.tree.primitive;
  EXPECT_NEAR(p.volume(), 32.0 * 20 * 12, 0.01 * 32 * 20 * 12);
  EXPECT_GT(r.fit.stats.iou, 0.99);
  // The box's own axes are the block's edges.
  EXPECT_LT(frame_difference_deg(p.rotation, q), 0.5);
}

}  // namespace
}  // namespace csgfit
