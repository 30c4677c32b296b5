// fit_heights: least squares of a height field's control net to scattered points.
#include "csgfit/model/bspline_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace csgfit;

namespace {

const XYRectangle kRect{-1, 2, 0, 1.5};

BSplineSurface random_height_field(int nu, int nv, int p, int q, std::mt19937_64& rng,
                                   NetSpacing spacing = NetSpacing::Greville) {
  std::uniform_real_distribution<double> d(-1, 1);
  std::vector<double> heights(static_cast<std::size_t>(nu * nv));
  for (double& z : heights) z = d(rng);
  return BSplineSurface::height_field(BSplineBasis(nu, p), BSplineBasis(nv, q), kRect, heights,
                                      spacing);
}

// A 31 x 31 grid over the rectangle and 300 scattered points, z from `f`.
template <class F>
std::vector<Vec3> samples(F f, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> x(kRect.x0, kRect.x1), y(kRect.y0, kRect.y1);
  std::vector<Vec3> pts;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 30; ++i) {
      const double px = kRect.x0 + (kRect.x1 - kRect.x0) * i / 30.0;
      const double py = kRect.y0 + (kRect.y1 - kRect.y0) * j / 30.0;
      pts.push_back({px, py, f(px, py)});
    }
  for (int k = 0; k < 300; ++k) {
    const double px = x(rng), py = y(rng);
    pts.push_back({px, py, f(px, py)});
  }
  return pts;
}

// The largest |a - f| over a 101 x 101 grid of the rectangle.
template <class F>
double max_deviation(const BSplineSurface& a, F f) {
  double worst = 0;
  for (int j = 0; j <= 100; ++j)
    for (int i = 0; i <= 100; ++i) {
      const double x = kRect.x0 + (kRect.x1 - kRect.x0) * i / 100.0;
      const double y = kRect.y0 + (kRect.y1 - kRect.y0) * j / 100.0;
      worst = std::max(worst, std::abs(a.height_at(x, y) - f(x, y)));
    }
  return worst;
}

}  // namespace

TEST(BSplineFit, RecoversAnExactSurfaceFromItsOwnSamples) {
  std::mt19937_64 rng(11);
  const int sizes[][4] = {{6, 8, 3, 3}, {4, 15, 3, 3}, {5, 5, 2, 3}, {9, 4, 1, 2}};
  for (const auto& n : sizes) {
    const BSplineSurface truth = random_height_field(n[0], n[1], n[2], n[3], rng);
    const auto f = [&](double x, double y) { return truth.height_at(x, y); };
    for (double smoothing : {0.0, 1e-13}) {
      const HeightFit fit = fit_heights(samples(f, rng), kRect, n[0], n[1], n[2], n[3], smoothing);
      EXPECT_LT(fit.max_residual, 1e-9);
      EXPECT_LT(fit.rms, 1e-9);
      for (std::size_t c = 0; c < truth.net().size(); ++c)
        EXPECT_NEAR(fit.surface.net()[c][2], truth.net()[c][2], 1e-9);
      EXPECT_LT(max_deviation(fit.surface, f), 1e-9);
    }
  }
}

// On equally spaced columns the fit recovers its own surface as well; the Greville fit of the
// same net does not (x(u) differs), which is why the patch fit tries both.
TEST(BSplineFit, RecoversAnExactSurfaceOnEquallySpacedColumns) {
  std::mt19937_64 rng(15);
  const BSplineSurface truth = random_height_field(8, 5, 3, 3, rng, NetSpacing::Uniform);
  const auto f = [&](double x, double y) { return truth.height_at(x, y); };
  const std::vector<Vec3> pts = samples(f, rng);
  const HeightFit fit = fit_heights(pts, kRect, 8, 5, 3, 3, 0.0, NetSpacing::Uniform);
  EXPECT_LT(fit.max_residual, 1e-9);
  for (std::size_t c = 0; c < truth.net().size(); ++c)
    EXPECT_NEAR(fit.surface.net()[c][2], truth.net()[c][2], 1e-9);
  EXPECT_LT(max_deviation(fit.surface, f), 1e-9);
  EXPECT_GT(fit_heights(pts, kRect, 8, 5, 3, 3, 0.0).max_residual, 1e-3);
  // A plane costs nothing under the smoothing on unequal column gaps too.
  const auto plane = [](double x, double y) { return 1 + 2 * x - 3 * y; };
  EXPECT_LT(max_deviation(fit_heights(samples(plane, rng), kRect, 8, 5, 3, 3, 1e-2, NetSpacing::Uniform).surface,
                          plane), 1e-9);
}

TEST(BSplineFit, NoiseStaysBounded) {
  std::mt19937_64 rng(12);
  const BSplineSurface truth = random_height_field(6, 7, 3, 3, rng);
  const auto f = [&](double x, double y) { return truth.height_at(x, y); };
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  std::vector<Vec3> pts = samples(f, rng);
  for (Vec3& p : pts) p[2] += noise(rng);
  const HeightFit fit = fit_heights(pts, kRect, 6, 7, 3, 3, 1e-6);
  // Residuals are the noise (sd 0.01 / sqrt(3)); the surface averages it out, to less than the
  // noise's amplitude even at the corners, where the fewest points hold it.
  EXPECT_LT(fit.max_residual, 0.02);
  EXPECT_NEAR(fit.rms, 0.01 / std::sqrt(3.0), 0.001);
  EXPECT_LT(max_deviation(fit.surface, f), 0.01);
}

TEST(BSplineFit, ApproximatesASmoothFunction) {
  std::mt19937_64 rng(13);
  const auto f = [](double x, double y) { return std::sin(1.3 * x) * std::cos(2 * y) + 0.2 * x * y; };
  const HeightFit fit = fit_heights(samples(f, rng), kRect, 12, 10, 3, 3, 1e-8);
  EXPECT_LT(fit.max_residual, 2e-4);
  EXPECT_LT(max_deviation(fit.surface, f), 2e-4);
  // The same over the points' own bounding box (the grid spans the rectangle).
  const HeightFit own = fit_heights(samples(f, rng), 12, 10);
  EXPECT_DOUBLE_EQ(own.surface.rectangle().x0, kRect.x0);
  EXPECT_DOUBLE_EQ(own.surface.rectangle().y1, kRect.y1);
  EXPECT_LT(own.max_residual, 2e-4);
}

// A gap in the scan leaves control points with no point under them: the smoothing carries the
// plane across it (a plane costs nothing under divided second differences); without smoothing
// the fit refuses.
TEST(BSplineFit, SmoothingDefinesTheNetOverAGap) {
  std::mt19937_64 rng(14);
  const auto plane = [](double x, double y) { return 1 + 2 * x - 3 * y; };
  std::vector<Vec3> pts;
  for (const Vec3& p : samples(plane, rng))
    if (p[0] < 0 || p[0] > 1.2) pts.push_back(p);
  // 16 control points in x: knot spans of 0.23, so some supports (4 spans) lie in the gap.
  const HeightFit fit = fit_heights(pts, kRect, 16, 6, 3, 3, 1e-4);
  EXPECT_LT(max_deviation(fit.surface, plane), 1e-9);
  EXPECT_THROW(fit_heights(pts, kRect, 16, 6, 3, 3, 0.0), std::invalid_argument);
}

TEST(BSplineFit, RejectsPointsThatCannotDetermineANet) {
  const std::vector<Vec3> few = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(fit_heights(few, 4, 4), std::invalid_argument);
  std::vector<Vec3> line;
  for (int k = 0; k < 50; ++k) line.push_back({-1 + k * 0.06, k * 0.03, 1.0});
  EXPECT_THROW(fit_heights(line, kRect, 4, 4, 3, 3, 1e-3), std::invalid_argument);
  EXPECT_THROW(fit_heights(line, 5, 6), std::invalid_argument);
  std::vector<Vec3> flat_x;
  for (int k = 0; k < 50; ++k) flat_x.push_back({1.0, k * 0.1, 1.0});
  EXPECT_THROW(fit_heights(flat_x, 4, 4), std::invalid_argument);
  std::vector<Vec3> bad = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, std::nan("")}};
  EXPECT_THROW(fit_heights(bad, 4, 4), std::invalid_argument);
  bad[3][2] = 0;
  bad[2][0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fit_heights(bad, 4, 4), std::invalid_argument);
  EXPECT_THROW(fit_heights(few, kRect, 4, 4, 3, 3, -1.0), std::invalid_argument);
}
