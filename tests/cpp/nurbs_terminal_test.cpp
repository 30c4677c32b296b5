// Seed 004's NURBS terminal as a 3D primitive: its solid, volume, z-rays, JSON and .scad.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "csgfit/search/point_fitness.h"
#include "scad_writer3d.h"

using namespace csgfit;

namespace {

// A 6 x 4 patch over 40 x 20 whose heights rise with x and bulge in y: 5 .. ~12.
Primitive3D dome(const Quaternion& q = {}, NetSpacing spacing = NetSpacing::Greville) {
  const int nu = 6, nv = 4;
  std::vector<double> h;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) h.push_back(5 + i + 2.0 * (j == 1 || j == 2));
  BSplineSurface s = BSplineSurface::height_field(BSplineBasis(nu, 3), BSplineBasis(nv, 3),
                                                  {-20, 20, -10, 10}, h, spacing);
  return Primitive3D::nurbs(3, -2, 1, std::move(s), q);
}

// The integral of S over the rectangle by the midpoint rule on a fine grid (independent of the
// Gauss rule volume() uses).
double midpoint_volume(const Primitive3D& p, int n) {
  double v = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -20 + 40 * (i + 0.5) / n, y = -10 + 20 * (j + 0.5) / n;
      v += std::max(0.0, p.patch->height_at(x, y));
    }
  return v * 800.0 / (n * n);
}

}  // namespace

TEST(NurbsTerminal, SolidIsBetweenFloorAndPatch) {
  const Primitive3D p = dome();
  EXPECT_EQ(p.kind, PrimitiveKind3D::Nurbs);
  EXPECT_DOUBLE_EQ(p.dims[0], 40);
  EXPECT_DOUBLE_EQ(p.dims[1], 20);
  const double top = p.patch->height_at(4, 1);  // local (4, 1) is model (7, -1)
  EXPECT_TRUE(p.contains(7, -1, 1 + 0.001));
  EXPECT_TRUE(p.contains(7, -1, 1 + top - 1e-6));
  EXPECT_FALSE(p.contains(7, -1, 1 + top + 1e-6));
  EXPECT_FALSE(p.contains(7, -1, 1 - 1e-6));   // below the floor
  EXPECT_FALSE(p.contains(24, -1, 3));          // beside the rectangle
  EXPECT_LT(p.signed_distance(7, -1, 2), 0);
  EXPECT_GT(p.signed_distance(7, -1, 1 + top + 0.5), 0);
  EXPECT_NEAR(p.signed_distance(7, -1, -1), 2, 1e-9);  // straight below the floor
}

TEST(NurbsTerminal, VolumeIsTheIntegralOfThePatch) {
  for (NetSpacing spacing : {NetSpacing::Greville, NetSpacing::Uniform}) {
    const Primitive3D p = dome({}, spacing);
    EXPECT_NEAR(p.volume(), midpoint_volume(p, 800), 1e-4 * p.volume());
  }
  // Equally spaced columns are another surface over the same rectangle (not a vacuous loop).
  EXPECT_GT(std::abs(dome({}, NetSpacing::Uniform).patch->height_at(-17, 0) - dome().patch->height_at(-17, 0)), 0.05);
}

TEST(NurbsTerminal, RasterisedVolumeAndBoundsAgree) {
  const Primitive3D p = dome(Quaternion::from_axis_angle(1, 1, 0, 20));
  const Bounds3 b = p.bounds();
  const double vs = 0.25;
  VoxelGrid g(static_cast<int>((b.hi[0] - b.lo[0]) / vs) + 2, static_cast<int>((b.hi[1] - b.lo[1]) / vs) + 2,
              static_cast<int>((b.hi[2] - b.lo[2]) / vs) + 2, b.lo[0] - vs, b.lo[1] - vs, b.lo[2] - vs, vs);
  rasterize(p, g);
  EXPECT_NEAR(static_cast<double>(g.count()) * vs * vs * vs, p.volume(), 0.01 * p.volume());
}

TEST(NurbsTerminal, ZRayMeetsThePatchTopAndTheTreeOperators) {
  const Primitive3D p = dome();
  const Node3D alone = Node3D::leaf(p);
  EXPECT_NEAR(column_top(alone, 7, -1), 1 + p.patch->height_at(4, 1), 1e-12);
  EXPECT_EQ(column_top(alone, 40, 0), -std::numeric_limits<double>::infinity());
  // A box cut out of the top lowers the column to the box's bottom.
  const Node3D cut = Node3D::op(NodeKind::Difference, {alone, Node3D::leaf(Primitive3D::box(7, -1, 20, 2, 2, 30))});
  EXPECT_NEAR(column_top(cut, 7, -1), 5, 1e-12);
  // A tilted patch is sampled: its z-ray still finds the top within the bisection's tolerance.
  const Primitive3D tilted = dome(Quaternion::from_axis_angle(0, 1, 0, 10));
  const double z = column_top(Node3D::leaf(tilted), 3, -2);
  EXPECT_TRUE(tilted.contains(3, -2, z - 1e-6));
  EXPECT_FALSE(tilted.contains(3, -2, z + 1e-6));
}

TEST(NurbsTerminal, JsonRoundTripKeepsThePatch) {
  for (NetSpacing spacing : {NetSpacing::Greville, NetSpacing::Uniform}) {
  FitResult3D r;
  r.tree = Node3D::op(NodeKind::Difference,
                      {Node3D::leaf(dome(Quaternion::from_axis_angle(0, 0, 1, 30), spacing)),
                       Node3D::leaf(Primitive3D::sphere(3, -2, 12, 4))});
  const VoxelGrid grid(4, 4, 4, 0, 0, 0, 1);
  const std::string text = to_json3d(r, grid, "dome.xyz");
  EXPECT_NE(text.find("\"nurbs\""), std::string::npos);
  EXPECT_NE(text.find("\"control_points\""), std::string::npos);
  const Node3D back = from_json3d(text);
  ASSERT_EQ(back.children.size(), 2u);
  const Primitive3D& a = r.tree.children[0].primitive;
  const Primitive3D& b = back.children[0].primitive;
  ASSERT_EQ(b.kind, PrimitiveKind3D::Nurbs);
  for (double x : {-15.0, 0.0, 11.0})
    EXPECT_NEAR(b.patch->height_at(x, 3), a.patch->height_at(x, 3), 1e-9);
  EXPECT_NEAR(b.volume(), a.volume(), 1e-9 * a.volume());
  }
}

// The reader evaluates z = S(x, y): each column must keep one x, the x increase, and the end
// columns be the rectangle's sides; each way off that is named.
TEST(NurbsTerminal, JsonRefusesANetOffItsGrid) {
  FitResult3D r;
  r.tree = Node3D::leaf(dome({}, NetSpacing::Uniform));
  const std::string text = to_json3d(r, VoxelGrid(4, 4, 4, 0, 0, 0, 1), "dome.xyz");
  const auto error_of = [](const std::string& t) -> std::string {
    try {
      from_json3d(t);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const auto edit = [&](const char* pattern, const char* by) {
    return std::regex_replace(text, std::regex(pattern), by, std::regex_constants::format_first_only);
  };
  // The first control point alone moved: its column no longer keeps one x.
  EXPECT_NE(error_of(edit("\"control_points\": \\[\\s*\\[\\s*-20", "\"control_points\": [[-19")).find("grid"),
            std::string::npos);
  // The whole first column moved in: the net no longer spans the rectangle.
  EXPECT_NE(error_of(std::regex_replace(text, std::regex("\\[\\s*-20(\\.0)?,"), "[-19,")).find("sides"),
            std::string::npos);
  // The second and third columns (x = -12 and -4 of six equally spaced over 40) swapped: the
  // net folds.
  const std::string folded = std::regex_replace(
      std::regex_replace(std::regex_replace(text, std::regex("\\[\\s*-12(\\.0)?,"), "[@,"),
                         std::regex("\\[\\s*-4(\\.0)?,"), "[-12,"),
      std::regex("\\[@,"), "[-4,");
  EXPECT_NE(error_of(folded).find("increasing"), std::string::npos) << error_of(folded);
  EXPECT_EQ(error_of(text), "");
}

TEST(NurbsTerminal, ScadPolyhedronStatesItsDeviation) {
  const std::string scad = to_scad(Node3D::leaf(dome()));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(scad, m, std::regex("nurbs_1: polyhedron of (\\d+)x(\\d+) cells, deviation <= ([0-9.e-]+) mm")))
      << scad.substr(0, 600);
  EXPECT_LE(std::stod(m[3]), 1e-4 * 40 * 1.0001);
  EXPECT_NE(scad.find("polyhedron(points = ["), std::string::npos);
}
