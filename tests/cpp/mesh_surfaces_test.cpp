// The surfaces read off a mesh's own triangles (issue 42): every face of a part OpenSCAD made is
// found with its exact parameters, regular polygon prisms as such, turned profiles as cones,
// tori and spheres.
#include "csgfit/features/mesh_surfaces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "openscad_meshes.h"

namespace csgfit {
namespace {

using testing::have_openscad;
using testing::openscad_mesh;

int count_kind(const MeshSurfaces& s, SurfaceKind kind) {
  return static_cast<int>(std::count_if(s.surfaces.begin(), s.surfaces.end(),
                                        [&](const MeshSurface& m) { return m.shape.kind == kind; }));
}

const MeshSurface* first_of(const MeshSurfaces& s, SurfaceKind kind) {
  for (const auto& m : s.surfaces)
    if (m.shape.kind == kind) return &m;
  return nullptr;
}

class MeshSurfacesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_openscad()) GTEST_SKIP() << "openscad is not installed";
  }
};

TEST_F(MeshSurfacesTest, AHexNutTrapIsOneSixSidedPrismInABox) {
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "difference() { cube([20, 20, 5], center = true);"
      " translate([2, 1, 0]) cylinder(r = 3, h = 10, center = true, $fn = 6); }"));
  EXPECT_EQ(count_kind(s, SurfaceKind::Plane), 6);
  ASSERT_EQ(count_kind(s, SurfaceKind::Cylinder), 1);
  const MeshSurface& hole = *first_of(s, SurfaceKind::Cylinder);
  EXPECT_EQ(hole.sides, 6);
  EXPECT_NEAR(hole.shape.radius, 3, 1e-4);
  EXPECT_FALSE(hole.shape.convex);
  EXPECT_NEAR(std::abs(hole.shape.axis[2]), 1, 1e-6);
  EXPECT_NEAR(hole.shape.point[0], 2, 1e-4);
  EXPECT_NEAR(hole.shape.point[1], 1, 1e-4);
  // OpenSCAD puts vertex 0 on +x: every vertex is at a multiple of 60 degrees.
  const double degrees = std::atan2(hole.vertex_direction[1], hole.vertex_direction[0]) * 180 / M_PI;
  EXPECT_NEAR(std::remainder(degrees, 60.0), 0, 1e-3);
  EXPECT_TRUE(s.unexplained.empty());
}

TEST_F(MeshSurfacesTest, ABossOnAPlateIsARoundCylinderOfItsRadius) {
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "cube([30, 20, 4]); translate([10, 10, 0]) cylinder(r = 5, h = 12, $fn = 60);"));
  ASSERT_EQ(count_kind(s, SurfaceKind::Cylinder), 1);
  const MeshSurface& boss = *first_of(s, SurfaceKind::Cylinder);
  EXPECT_TRUE(boss.shape.convex);
  EXPECT_EQ(boss.sides, 60);
  EXPECT_NEAR(boss.shape.radius, 5, 1e-4);
  EXPECT_NEAR(boss.hi - boss.lo, 8, 1e-4);  // above the plate only
  EXPECT_TRUE(s.unexplained.empty());
}

TEST_F(MeshSurfacesTest, ARoundedRectangleIsFourCornerArcsAndItsSides) {
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "linear_extrude(height = 5) offset(r = 3, $fn = 40) square([20, 10], center = true);"));
  EXPECT_EQ(count_kind(s, SurfaceKind::Cylinder), 4);
  EXPECT_EQ(count_kind(s, SurfaceKind::Plane), 6);
  for (const auto& m : s.surfaces)
    if (m.shape.kind == SurfaceKind::Cylinder) {
      EXPECT_NEAR(m.shape.radius, 3, 1e-3);
      EXPECT_TRUE(m.shape.convex);
    }
}

TEST_F(MeshSurfacesTest, ATurnedPartIsItsProfilesConeTorusAndPlanes) {
  // A frustum with a rounded top edge (a quarter-circle fillet) and a bore.
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "rotate_extrude($fn = 48) difference() {"
      " hull() { square([12, 1]); translate([8, 8]) circle(r = 2, $fn = 32);"
      " square([2, 10]); } square([3, 30], center = true); }"));
  EXPECT_GE(count_kind(s, SurfaceKind::Torus), 1);
  EXPECT_GE(count_kind(s, SurfaceKind::Cone), 1);
  ASSERT_NE(first_of(s, SurfaceKind::Torus), nullptr);
  EXPECT_NEAR(first_of(s, SurfaceKind::Torus)->shape.minor_radius, 2, 0.02);
  EXPECT_NEAR(first_of(s, SurfaceKind::Torus)->shape.radius, 8, 0.02);
}

TEST_F(MeshSurfacesTest, ABallIsOneSphere) {
  const auto s = segment_mesh_surfaces(openscad_mesh("translate([1, 2, 3]) sphere(r = 7, $fn = 36);"));
  ASSERT_EQ(count_kind(s, SurfaceKind::Sphere), 1);
  const MeshSurface& ball = *first_of(s, SurfaceKind::Sphere);
  EXPECT_NEAR(ball.shape.radius, 7, 0.02);
  EXPECT_TRUE(ball.shape.convex);
}

// A ball bored along x, y and z: its facets cut by the bores have corners on their own chord
// planes, and its columns of facets would pass for narrow cylinders; it is still one sphere.
TEST_F(MeshSurfacesTest, ABallBoredThroughIsOneSphereAndItsBores) {
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "difference() { sphere(r = 15, $fn = 64); cylinder(r = 5, h = 40, center = true, $fn = 48);"
      " rotate([90, 0, 0]) cylinder(r = 5, h = 40, center = true, $fn = 48);"
      " rotate([0, 90, 0]) cylinder(r = 5, h = 40, center = true, $fn = 48); }"));
  ASSERT_EQ(count_kind(s, SurfaceKind::Sphere), 1);
  EXPECT_NEAR(first_of(s, SurfaceKind::Sphere)->shape.radius, 15, 0.02);
  EXPECT_EQ(count_kind(s, SurfaceKind::Cylinder), 3);
}

// Any two coaxial circles lie on a sphere: a washer's short walls are cylinders, not balls.
TEST_F(MeshSurfacesTest, AWashersShortWallsAreCylindersNotBalls) {
  const auto s = segment_mesh_surfaces(openscad_mesh(
      "difference() { cylinder(r = 12, h = 1.5, $fn = 60); translate([0, 0, -1]) cylinder(r = 4, h = 4, $fn = 40); }"));
  EXPECT_EQ(count_kind(s, SurfaceKind::Sphere), 0);
  EXPECT_EQ(count_kind(s, SurfaceKind::Cylinder), 2);
}

}  // namespace
}  // namespace csgfit
