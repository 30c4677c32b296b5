// The whole 2D fit: accuracy on shapes with a known tree, determinism, budgets, cancellation.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/pipeline/fit_bitmap.h"

using namespace csgfit;

namespace {

// A bracket-like part: plate minus a hole, plus a rotated tab.
Bitmap bracket() {
  const Node truth = Node::op(
      NodeKind::Union,
      {Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(50, 40, 70, 44, 0)),
                                       Node::leaf(Primitive::circle(40, 40, 11))}),
       Node::leaf(Primitive::ellipse(88, 64, 18, 9, 40))});
  return render(truth, 112, 96);
}

FitOptions quick(std::uint64_t seed = 1, int threads = 1) {
  FitOptions o;
  o.seed = seed;
  o.threads = threads;
  o.time_limit = 60;  // generous: these runs end by convergence, which keeps them deterministic
  o.search.max_stale = 300;
  o.search.max_trees = 1500;
  return o;
}

}  // namespace

TEST(Fit, RecoversAPartWithFewPrimitivesAndHighIoU) {
  const Bitmap target = bracket();
  const FitResult r = fit_bitmap(target, quick());
  const Bitmap raster = render(r.tree, r.width, r.height);
  EXPECT_GT(iou(raster, target), 0.98) << structure_string(r.tree);
  EXPECT_LE(r.tree.primitive_count(), 4u) << structure_string(r.tree);
  // The reported stats are those of the returned tree.
  EXPECT_NEAR(r.stats.iou, iou(raster, target), 1e-12);
  EXPECT_EQ(r.stats.primitives, r.tree.primitive_count());
  EXPECT_EQ(r.stats.excess, count_and_not(raster, target));
  EXPECT_EQ(r.stats.uncovered, count_and_not(target, raster));
}

TEST(Fit, SameSeedAndThreadsGiveTheSameTree) {
  const Bitmap target = bracket();
  for (int threads : {1, 2}) {
    const FitResult a = fit_bitmap(target, quick(42, threads));
    const FitResult b = fit_bitmap(target, quick(42, threads));
    EXPECT_EQ(a.tree, b.tree) << threads << " threads: " << structure_string(a.tree) << " vs "
                              << structure_string(b.tree);
    EXPECT_EQ(a.stats.score, b.stats.score);
  }
}

TEST(Fit, AllForegroundIsOneRectangle) {
  Bitmap full(40, 30);
  full.fill();
  const FitResult r = fit_bitmap(full, quick());
  EXPECT_EQ(r.tree.primitive_count(), 1u);
  EXPECT_EQ(r.tree.primitive.kind, PrimitiveKind::Rectangle);
  EXPECT_EQ(r.stats.iou, 1.0);
}

// The size weight scales with the pixel count; the paper's preset keeps its Table 2 weight.
TEST(Fit, SizeWeightFollowsTheImageAreaAndThePreset) {
  Bitmap half(128, 64);
  half.fill();
  EXPECT_DOUBLE_EQ(fit_bitmap(half, quick()).stats.k, SearchParams{}.k_at_128 / 2);
  FitOptions paper = quick();
  paper.search = SearchParams::for_quality("paper");
  EXPECT_DOUBLE_EQ(fit_bitmap(half, paper).stats.k, 12.5);
  FitOptions given = quick();
  given.k = 3;
  EXPECT_DOUBLE_EQ(fit_bitmap(half, given).stats.k, 3);
}

TEST(Fit, TinyImagesWork) {
  Bitmap one(1, 1);
  one.set(0, 0);
  const FitResult r = fit_bitmap(one, quick());
  EXPECT_EQ(r.stats.iou, 1.0);
}

TEST(Fit, EmptyTargetIsAnError) {
  EXPECT_THROW(fit_bitmap(Bitmap(16, 16), quick()), std::invalid_argument);
  EXPECT_THROW(fit_bitmap(Bitmap(0, 0), quick()), std::invalid_argument);
}

TEST(Fit, HonoursThePrimitiveList) {
  const Bitmap target = bracket();
  FitOptions o = quick();
  o.primitives = PrimitiveSet::parse("rectangle,triangle");
  const FitResult r = fit_bitmap(target, o);
  for (const Primitive* p : leaves(r.tree))
    EXPECT_TRUE(p->kind == PrimitiveKind::Rectangle || p->kind == PrimitiveKind::Triangle);
  o.primitives = PrimitiveSet::parse("circle");  // no rectangles: no seed-003 boxes either
  const FitResult c = fit_bitmap(target, o);
  for (const Primitive* p : leaves(c.tree)) EXPECT_EQ(p->kind, PrimitiveKind::Circle);
}

TEST(Fit, ReturnsStructurallyDifferentAlternatives) {
  FitOptions o = quick();
  o.alternatives = 3;
  const FitResult r = fit_bitmap(bracket(), o);
  ASSERT_FALSE(r.alternatives.empty());
  for (const FitTree& alt : r.alternatives) {
    EXPECT_NE(structure_string(alt.tree), structure_string(r.tree));
    EXPECT_GE(alt.stats.score, r.stats.score);
  }
}

TEST(Fit, CancelStopsPromptlyWithTheBestSoFar) {
  const Bitmap target = bracket();
  FitOptions o = quick();
  o.time_limit = 60;
  o.search.max_stale = 1 << 30;
  o.search.max_trees = 1 << 30;
  std::atomic<bool> cancel{false};
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const auto t0 = std::chrono::steady_clock::now();
  const FitResult r = fit_bitmap(target, o, nullptr, &cancel);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  canceller.join();
  EXPECT_LT(s, 1.5);
  EXPECT_EQ(r.stats.stop_reason, "cancelled");
  EXPECT_GT(r.stats.iou, 0.5);
}

TEST(Fit, ProgressCallbackCanCancel) {
  FitOptions o = quick();
  o.search.max_stale = 1 << 30;
  o.search.max_trees = 1 << 30;
  int calls = 0;
  const FitResult r = fit_bitmap(bracket(), o, [&](const FitProgress& p) {
    EXPECT_GE(p.fraction, 0.0);
    EXPECT_LE(p.fraction, 1.0);
    return ++calls < 3;
  });
  EXPECT_EQ(r.stats.stop_reason, "cancelled");
}

TEST(Fit, TimeBudgetIsRespected) {
  FitOptions o = quick();
  o.time_limit = 0.5;
  o.search.max_stale = 1 << 30;
  o.search.max_trees = 1 << 30;
  const FitResult r = fit_bitmap(bracket(), o);
  EXPECT_EQ(r.stats.stop_reason, "time");
  // Generous: only that it stops, not how fast the machine is.
  EXPECT_LT(r.stats.seconds, 5.0);
}

TEST(Fit, NoPixelCentreLiesOnAPrimitiveBoundary) {
  // Otherwise OpenSCAD or FreeCAD could draw a pixel the solver counted, or drop one.
  Bitmap target(64, 48);
  for (int r = 10; r < 40; ++r) target.set_span(r, 8, 50);  // edges on pixel boundaries
  const FitResult res = fit_bitmap(target, quick());
  for (const Primitive* p : leaves(res.tree)) {
    Bitmap exact(64, 48), nudged(64, 48);
    rasterize(*p, exact);
    for (double d : {-2e-4, 2e-4}) {
      Primitive q = *p;
      q.w += d;
      q.h += d;
      rasterize(q, nudged);
      EXPECT_EQ(exact, nudged) << to_string(p->kind) << " cx " << p->cx << " w " << p->w;
    }
  }
}
