// The 3D fit: seed 003's decomposition, the local optimiser and the hill climb together.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>

#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/model/tree3d.h"

using namespace csgfit;

namespace {

VoxelGrid box_minus_cylinder() {
  const Node3D truth = Node3D::op(
      NodeKind::Difference,
      {Node3D::leaf(Primitive3D::box(24.2, 23.9, 24.1, 34, 26, 14, Quaternion::from_euler_deg(0, 0, 12))),
       Node3D::leaf(Primitive3D::cylinder(22.3, 25.1, 24, 6.5, 20))});
  return render(truth, VoxelGrid(48, 48, 48, -3, 2, 1, 1.0));
}

}  // namespace

TEST(Fit3D, DefaultKScalesWithTheGrid) {
  EXPECT_DOUBLE_EQ(default_k3d(VoxelGrid(100, 100, 100)), 140);
  EXPECT_DOUBLE_EQ(default_k3d(VoxelGrid(200, 100, 100)), 280);
  EXPECT_DOUBLE_EQ(default_k3d(VoxelGrid(10, 10, 10)), 8);
}

TEST(Fit3D, RecoversABoxWithAHole) {
  const VoxelGrid target = box_minus_cylinder();
  FitOptions3D opt;
  // Ended by convergence, not the clock: a sanitizer build is several times slower.
  opt.time_limit = 120;
  opt.search.max_stale = 40;
  opt.threads = 1;
  opt.k = 60;
  const FitResult3D r = fit_voxels(target, opt);
  std::printf("IoU %.4f, %zu primitives: %s\n", r.stats.iou, r.stats.primitives,
              structure_string(r.tree).c_str());
  EXPECT_GT(r.stats.iou, 0.97);
  EXPECT_LE(r.stats.primitives, 3u) << structure_string(r.tree);
  EXPECT_EQ(r.stats.primitives, r.tree.primitive_count());
  // The stats describe the returned tree.
  const VoxelGrid fitted = render(r.tree, target);
  EXPECT_EQ(count_and_not(fitted, target), r.stats.excess);
  EXPECT_EQ(count_and_not(target, fitted), r.stats.uncovered);
  EXPECT_NEAR(iou(fitted, target), r.stats.iou, 1e-12);
}

TEST(Fit3D, SameSeedSameTreeWhenConverged) {
  const VoxelGrid target = box_minus_cylinder();
  FitOptions3D opt;
  opt.time_limit = 60;
  opt.threads = 2;
  opt.search.max_stale = 16;
  const FitResult3D a = fit_voxels(target, opt);
  const FitResult3D b = fit_voxels(target, opt);
  ASSERT_EQ(a.stats.stop_reason, "converged");
  EXPECT_TRUE(a.tree == b.tree);
  EXPECT_EQ(a.stats.trees, b.stats.trees);
}

TEST(Fit3D, CancelReturnsATree) {
  const VoxelGrid target = box_minus_cylinder();
  std::atomic<bool> cancel{true};
  FitOptions3D opt;
  opt.time_limit = 30;
  opt.threads = 1;
  const FitResult3D r = fit_voxels(target, opt, nullptr, &cancel);
  EXPECT_EQ(r.stats.stop_reason, "cancelled");
  EXPECT_GE(r.tree.primitive_count(), 1u);
  int calls = 0;
  const FitResult3D r2 = fit_voxels(target, opt, [&](const FitProgress&) { return ++calls < 2; });
  EXPECT_EQ(r2.stats.stop_reason, "cancelled");
  // A cancel reaches the seed's decomposition and polish too (the first progress report comes
  // only after them), so a fit cancelled from the start does a fraction of their work.
  EXPECT_LT(r.stats.evaluations * 4, r2.stats.evaluations);
}

TEST(Fit3D, RejectsBadInput) {
  FitOptions3D opt;
  EXPECT_THROW(fit_voxels(VoxelGrid(8, 8, 8), opt), std::invalid_argument);
  const VoxelGrid target = box_minus_cylinder();
  opt.time_limit = 0;
  EXPECT_THROW(fit_voxels(target, opt), std::invalid_argument);
  opt.time_limit = 1;
  opt.primitives = PrimitiveSet3D{};
  EXPECT_THROW(fit_voxels(target, opt), std::invalid_argument);
}
