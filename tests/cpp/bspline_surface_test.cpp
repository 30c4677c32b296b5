// B-spline bases and surfaces: the invariants of the basis (partition of unity, non-negativity,
// the recursive definition, derivatives), end interpolation, the height field's x-y map.
#include "csgfit/model/bspline_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

using namespace csgfit;

namespace {

// The textbook recursion (half-open spans, the last one closed), as an independent reference.
double cox_de_boor(const std::vector<double>& t, int i, int p, double u) {
  if (p == 0) {
    const bool last = u == t.back() && t[i + 1] == t.back() && t[i] < t[i + 1];
    return (t[i] <= u && u < t[i + 1]) || last ? 1.0 : 0.0;
  }
  double a = 0, b = 0;
  if (t[i + p] > t[i]) a = (u - t[i]) / (t[i + p] - t[i]) * cox_de_boor(t, i, p - 1, u);
  if (t[i + p + 1] > t[i + 1])
    b = (t[i + p + 1] - u) / (t[i + p + 1] - t[i + 1]) * cox_de_boor(t, i + 1, p - 1, u);
  return a + b;
}

// N_i,p(u) for every i from the fast evaluation (zero outside its p + 1 nonzero ones).
std::vector<double> all_values(const BSplineBasis& b, double u) {
  std::vector<double> n(static_cast<std::size_t>(b.count()), 0.0);
  const BasisAt at = b.at(u);
  for (int r = 0; r <= b.degree(); ++r) n[at.first + r] = at.value[r];
  return n;
}

std::vector<BSplineBasis> sample_bases() {
  std::vector<BSplineBasis> bases;
  for (int p = 1; p <= 5; ++p)
    for (int n = p + 1; n <= p + 7; n += 2) bases.emplace_back(n, p);
  bases.emplace_back(std::vector<double>{0, 0, 0, 0, 0.2, 0.5, 0.5, 0.9, 1, 1, 1, 1}, 3);
  bases.emplace_back(std::vector<double>{0, 0, 0, 0.1, 0.1, 0.7, 1, 1, 1}, 2);
  return bases;
}

std::vector<Vec3> random_net(int nu, int nv, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  std::vector<Vec3> net(static_cast<std::size_t>(nu * nv));
  for (Vec3& c : net) c = {d(rng), d(rng), d(rng)};
  return net;
}

// n heights uniform in [-1, 1].
std::vector<double> random_heights(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  std::vector<double> heights(static_cast<std::size_t>(n));
  for (double& z : heights) z = d(rng);
  return heights;
}

}  // namespace

TEST(BSplineBasis, PartitionOfUnityAndNonNegative) {
  for (const BSplineBasis& b : sample_bases())
    for (int k = 0; k <= 1000; ++k) {
      const double u = k / 1000.0;
      const BasisAt at = b.at(u);
      double sum = 0, slope_sum = 0;
      for (int r = 0; r <= b.degree(); ++r) {
        EXPECT_GE(at.value[r], 0.0);
        sum += at.value[r];
        slope_sum += at.slope[r];
      }
      EXPECT_NEAR(sum, 1.0, 1e-14) << "degree " << b.degree() << " u " << u;
      EXPECT_NEAR(slope_sum, 0.0, 1e-10);  // the derivative of 1
      EXPECT_GE(at.first, 0);
      EXPECT_LE(at.first + b.degree(), b.count() - 1);
    }
}

TEST(BSplineBasis, MatchesTheRecursiveDefinition) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> d(0, 1);
  for (const BSplineBasis& b : sample_bases())
    for (int k = 0; k < 200; ++k) {
      const double u = k == 0 ? 1.0 : d(rng);
      const std::vector<double> n = all_values(b, u);
      for (int i = 0; i < b.count(); ++i)
        EXPECT_NEAR(n[i], cox_de_boor(b.knots(), i, b.degree(), u), 1e-13);
    }
}

TEST(BSplineBasis, DerivativeMatchesFiniteDifferences) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> d(1e-3, 1 - 1e-3);
  const double h = 1e-6;
  for (const BSplineBasis& b : sample_bases())
    for (int k = 0; k < 200; ++k) {
      const double u = d(rng);
      if (b.span(u - h) != b.span(u + h)) continue;  // a degree 1 slope jumps at a knot
      const std::vector<double> lo = all_values(b, u - h), hi = all_values(b, u + h);
      const BasisAt at = b.at(u);
      for (int r = 0; r <= b.degree(); ++r) {
        const int i = at.first + r;
        EXPECT_NEAR(at.slope[r], (hi[i] - lo[i]) / (2 * h), 1e-5 * (1 + std::abs(at.slope[r])));
      }
    }
}

TEST(BSplineBasis, GrevilleAbscissaeGiveLinearPrecision) {
  for (const BSplineBasis& b : sample_bases())
    for (int k = 0; k <= 100; ++k) {
      const double u = k / 100.0;
      const BasisAt at = b.at(u);
      double x = 0;
      for (int r = 0; r <= b.degree(); ++r) x += at.value[r] * b.greville(at.first + r);
      EXPECT_NEAR(x, u, 1e-14);
    }
}

TEST(BSplineBasis, OpenUniformKnotsAndBadVectors) {
  const BSplineBasis b(6, 3);
  EXPECT_EQ(b.knots(), (std::vector<double>{0, 0, 0, 0, 1 / 3.0, 2 / 3.0, 1, 1, 1, 1}));
  EXPECT_EQ(b.span(0.0), 3);
  EXPECT_EQ(b.span(1.0), 5);
  EXPECT_THROW(BSplineBasis(3, 3), std::invalid_argument);
  EXPECT_THROW(BSplineBasis(5, 0), std::invalid_argument);
  EXPECT_THROW(BSplineBasis(20, kMaxBSplineDegree + 1), std::invalid_argument);
  using K = std::vector<double>;
  EXPECT_THROW(BSplineBasis(K{0, 0, 0.5, 1, 1, 1}, 2), std::invalid_argument);     // not clamped
  EXPECT_THROW(BSplineBasis(K{0, 0, 0, 0.6, 0.4, 1, 1, 1}, 2), std::invalid_argument);  // order
  EXPECT_THROW(BSplineBasis(K{0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, 2), std::invalid_argument);
  EXPECT_THROW(BSplineBasis(K{0, 0, 0, 0, 1, 1, 1}, 2), std::invalid_argument);  // knot at an end
  EXPECT_THROW(BSplineBasis(K{0, 0, 1}, 2), std::invalid_argument);
}

TEST(BSplineSurface, CornerControlPointsAreTheCorners) {
  std::mt19937_64 rng(6);
  for (int p = 1; p <= 4; ++p) {
    const int nu = p + 3, nv = p + 2;
    const BSplineSurface s(BSplineBasis(nu, p), BSplineBasis(nv, std::min(3, nv - 1)),
                           random_net(nu, nv, rng));
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(s.point(0, 0)[k], s.control_point(0, 0)[k], 1e-15);
      EXPECT_NEAR(s.point(1, 0)[k], s.control_point(nu - 1, 0)[k], 1e-15);
      EXPECT_NEAR(s.point(0, 1)[k], s.control_point(0, nv - 1)[k], 1e-15);
      EXPECT_NEAR(s.point(1, 1)[k], s.control_point(nu - 1, nv - 1)[k], 1e-15);
    }
  }
  EXPECT_THROW(BSplineSurface(BSplineBasis(4, 3), BSplineBasis(4, 3), std::vector<Vec3>(15)),
               std::invalid_argument);
}

TEST(BSplineSurface, PartialsAndNormalMatchFiniteDifferences) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> d(0.01, 0.99);
  const BSplineSurface s(BSplineBasis(7, 3), BSplineBasis(5, 2), random_net(7, 5, rng));
  const double h = 1e-6;
  for (int n = 0; n < 100; ++n) {
    const double u = d(rng), v = d(rng);
    const SurfaceFrame f = s.frame(u, v);
    const Vec3 pu = s.point(u + h, v), mu = s.point(u - h, v);
    const Vec3 pv = s.point(u, v + h), mv = s.point(u, v - h);
    double unit = 0, along_u = 0, along_v = 0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(f.du[k], (pu[k] - mu[k]) / (2 * h), 1e-5 * (1 + std::abs(f.du[k])));
      EXPECT_NEAR(f.dv[k], (pv[k] - mv[k]) / (2 * h), 1e-5 * (1 + std::abs(f.dv[k])));
      unit += f.normal[k] * f.normal[k];
      along_u += f.normal[k] * f.du[k];
      along_v += f.normal[k] * f.dv[k];
    }
    EXPECT_NEAR(unit, 1.0, 1e-12);
    EXPECT_NEAR(along_u, 0.0, 1e-10);
    EXPECT_NEAR(along_v, 0.0, 1e-10);
  }
}

TEST(BSplineSurface, HeightFieldFollowsTheRectangle) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> d(-1, 1);
  const int nu = 5, nv = 6;
  const std::vector<double> heights = random_heights(nu * nv, rng);
  const XYRectangle r{-2, 3, 1, 1.5};
  const BSplineSurface s =
      BSplineSurface::height_field(BSplineBasis(nu, 3), BSplineBasis(nv, 3), r, heights);
  EXPECT_NEAR(s.height_at(-2, 1), heights[0], 1e-15);
  EXPECT_NEAR(s.height_at(3, 1.5), heights.back(), 1e-15);
  const double h = 1e-6;
  for (int n = 0; n < 100; ++n) {
    const double x = 0.5 + 2.4 * d(rng), y = 1.25 + 0.24 * d(rng);
    const SurfaceFrame f = s.frame_at(x, y);
    EXPECT_NEAR(f.point[0], x, 1e-13);  // x and y linear in u and v
    EXPECT_NEAR(f.point[1], y, 1e-13);
    // The normal of z = S(x, y) is (-z_x, -z_y, 1), normalised: up, out of the solid below.
    const double zx = (s.height_at(x + h, y) - s.height_at(x - h, y)) / (2 * h);
    const double zy = (s.height_at(x, y + h) - s.height_at(x, y - h)) / (2 * h);
    const double len = std::sqrt(zx * zx + zy * zy + 1);
    EXPECT_NEAR(f.normal[0], -zx / len, 1e-6);
    EXPECT_NEAR(f.normal[1], -zy / len, 1e-6);
    EXPECT_NEAR(f.normal[2], 1 / len, 1e-6);
  }
  EXPECT_THROW(BSplineSurface::height_field(BSplineBasis(4, 3), BSplineBasis(4, 3),
                                            XYRectangle{1, 1, 0, 1}, std::vector<double>(16)),
               std::invalid_argument);
  EXPECT_THROW(BSplineSurface::height_field(BSplineBasis(4, 3), BSplineBasis(4, 3), r,
                                            std::vector<double>(15)),
               std::invalid_argument);
}

// Equally spaced control columns (a designer's control polygon): x(u) is a monotone cubic, not
// u itself, and (x, y) -> (u, v) is its inverse, so S above (x, y) is found exactly.
TEST(BSplineSurface, UniformColumnsAreInvertedToTheirParameters) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> d(-1, 1);
  const int nu = 9, nv = 5;
  const std::vector<double> heights = random_heights(nu * nv, rng);
  const XYRectangle r{-30, 30, -10, 10};
  const BSplineSurface s = BSplineSurface::height_field(BSplineBasis(nu, 3), BSplineBasis(nv, 3), r,
                                                        heights, NetSpacing::Uniform);
  for (int i = 0; i < nu; ++i) EXPECT_NEAR(s.columns_x()[i], -30 + 60.0 * i / (nu - 1), 1e-12);
  EXPECT_NEAR(s.height_at(-30, -10), heights[0], 1e-13);
  EXPECT_NEAR(s.height_at(30, 10), heights.back(), 1e-13);
  // Not the Greville surface: x(u) bends at the clamped ends.
  EXPECT_GT(std::abs(s.point(0.05, 0.5)[0] - (-30 + 60 * 0.05)), 0.5);
  for (int n = 0; n < 200; ++n) {
    const double x = 30 * d(rng), y = 10 * d(rng);
    const SurfaceFrame f = s.frame_at(x, y);
    EXPECT_NEAR(f.point[0], x, 1e-9);
    EXPECT_NEAR(f.point[1], y, 1e-9);
  }
  // Outside the rectangle the parameters clamp, as for Greville columns.
  EXPECT_EQ(s.parameters_of(-31, 12)[0], 0.0);
  EXPECT_EQ(s.parameters_of(-31, 12)[1], 1.0);
  EXPECT_EQ(s.parameters_of(std::nan(""), 0)[0], 0.0);
}

TEST(BSplineSurface, HeightFieldColumnsMustIncrease) {
  const std::vector<double> h(16, 1.0);
  EXPECT_THROW(BSplineSurface::height_field(BSplineBasis(4, 3), BSplineBasis(4, 3), {0, 2, 1, 3},
                                            {0, 1, 2, 3}, h),
               std::invalid_argument);
  EXPECT_THROW(BSplineSurface::height_field(BSplineBasis(4, 3), BSplineBasis(4, 3), {0, 1, 2},
                                            {0, 1, 2, 3}, h),
               std::invalid_argument);
  EXPECT_NO_THROW(BSplineSurface::height_field(BSplineBasis(4, 3), BSplineBasis(4, 3),
                                               {0, 0.1, 2.5, 3}, {0, 1, 2, 3}, h));
}
