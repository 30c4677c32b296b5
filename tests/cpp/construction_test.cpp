// Boundary to CSG (issue 42): programs people write, rendered by OpenSCAD, come back from their
// faces as the program: the same solid (IoU against the mesh's own voxels) with the designer's
// count of primitives, the same tree for the same seed, a valid tree from an inexact mesh.
#include "csgfit/construct/boundary_csg.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_surfaces.h"
#include "csgfit/model/voxelize.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "model/random.h"
#include "openscad_meshes.h"

namespace csgfit {
namespace {

using testing::have_openscad;
using testing::openscad_mesh;

// IoU of the tree against the mesh on a grid of `resolution` voxels along the longest side.
double iou_against(const TriangleMesh& mesh, const Node3D& tree, int resolution = 96) {
  VoxelizeOptions v;
  v.resolution = resolution;
  const VoxelGrid target = voxelize(mesh, v);
  const VoxelGrid drawn = render(tree, target);
  std::size_t both = 0, either = 0;
  for (int k = 0; k < target.nz(); ++k)
    for (int j = 0; j < target.ny(); ++j)
      for (int i = 0; i < target.nx(); ++i) {
        const bool a = target.get(i, j, k), b = drawn.get(i, j, k);
        both += a && b;
        either += a || b;
      }
  return either ? static_cast<double>(both) / static_cast<double>(either) : 0;
}

int count_leaves(const Node3D& tree, const std::function<bool(const Primitive3D&)>& is) {
  int n = 0;
  for (const Primitive3D* p : leaves(tree)) n += is(*p);
  return n;
}

class Construction3D : public ::testing::Test {
 protected:
  // The construction explains the mesh and renders it, in at most `most` primitives.
  static void expect_whole(const TriangleMesh& mesh, const Construction& c, std::size_t most) {
    EXPECT_LT(c.missed + c.extra, 0.002);
    EXPECT_GT(iou_against(mesh, c.tree, 128), 0.995);
    EXPECT_LE(c.tree.primitive_count(), most);
  }
  void SetUp() override {
    if (!have_openscad()) GTEST_SKIP() << "openscad is not installed";
  }
  // The mesh fit at --time 30, which must end by construction with `primitives`.
  static MeshFitResult fitted_by_construction(const TriangleMesh& mesh, std::size_t primitives) {
    FitOptions3D o;
    o.time_limit = 30;
    MeshFitResult fit = fit_mesh(mesh, o);
    EXPECT_EQ(fit.fit.stats.stop_reason, "constructed");
    EXPECT_EQ(fit.fit.tree.primitive_count(), primitives);
    return fit;
  }
  Construction built(const TriangleMesh& mesh, std::uint64_t seed = 1) {
    ConstructionOptions o;
    o.seed = seed;
    return construct_from_surfaces(segment_mesh_surfaces(mesh), o);
  }
};

// Where a voxel search piled up boxes (issue 42): crossing holes, intersected cylinders. Each
// comes back as its program's primitives.
TEST_F(Construction3D, CrossingHolesAndIntersectedCylindersAreTheirProgram) {
  const struct {
    const char* part;
    const char* program;
    std::size_t primitives;
  } parts[] = {
      {"a block with three bars and three crossing square holes",
       "difference() {"
       "  union() { cube(20, center = true); cube([40, 8, 8], center = true);"
       "            cube([8, 40, 8], center = true); cube([8, 8, 40], center = true); }"
       "  cube([50, 4, 4], center = true); cube([4, 50, 4], center = true); cube([4, 4, 50], center = true); }",
       7},
      {"a cube less a bore, cut by two crossed cylinders",
       "intersection() {"
       "  difference() { cube(20, center = true); cylinder(r = 5, h = 30, center = true, $fn = 64); }"
       "  rotate([90, 0, 0]) cylinder(r = 12, h = 30, center = true, $fn = 64);"
       "  rotate([0, 90, 0]) cylinder(r = 12, h = 30, center = true, $fn = 64); }",
       4},
  };
  for (const auto& p : parts) {
    SCOPED_TRACE(p.part);
    const TriangleMesh mesh = openscad_mesh(p.program);
    const Construction c = built(mesh);
    EXPECT_EQ(c.tree.primitive_count(), p.primitives);
    EXPECT_GT(iou_against(mesh, c.tree), 0.995);
  }
}

TEST_F(Construction3D, AHexNutTrapInAPlateIsTwoPrimitivesOneOfThemSixSided) {
  const TriangleMesh mesh = openscad_mesh(
      "difference() { cube([30, 20, 6]); translate([12, 9, 2]) cylinder(r = 3.2, h = 10, $fn = 6); }");
  const Construction c = built(mesh);
  EXPECT_EQ(c.tree.primitive_count(), 2u);
  EXPECT_EQ(count_leaves(c.tree, [](const Primitive3D& p) { return p.sides == 6; }), 1);
  EXPECT_GT(iou_against(mesh, c.tree), 0.999);
}

// Parts of constant section and turned parts, as designers draw them: each whole, in the few
// primitives of its program.
TEST_F(Construction3D, ExtrudedAndTurnedPartsComeBackWhole) {
  const struct {
    const char* part;
    const char* program;
  } parts[] = {
      {"a rounded-rectangle clip with two holes",
       "linear_extrude(height = 4) difference() {"
       "  offset(r = 3, $fn = 48) square([24, 6], center = true);"
       "  translate([-8, 0]) circle(r = 1.6, $fn = 24); translate([8, 0]) circle(r = 1.6, $fn = 24); }"},
      {"a foot: a frustum with a rounded top edge and a bore",
       "rotate_extrude($fn = 64) difference() {"
       "  hull() { square([12, 1]); translate([8, 8]) circle(r = 2, $fn = 32); square([2, 10]); }"
       "  square([3, 30], center = true); }"},
  };
  for (const auto& p : parts) {
    SCOPED_TRACE(p.part);
    const TriangleMesh mesh = openscad_mesh(p.program);
    expect_whole(mesh, built(mesh), 8);
  }
}

TEST_F(Construction3D, TheSameSeedGivesTheSameTree) {
  const TriangleMesh mesh = openscad_mesh(
      "difference() { cube([30, 20, 10]); translate([8, 10, -1]) cylinder(r = 4, h = 12, $fn = 40);"
      " translate([22, 10, 5]) rotate([0, 90, 0]) cylinder(r = 2, h = 20, center = true, $fn = 8); }");
  EXPECT_EQ(built(mesh, 7).tree, built(mesh, 7).tree);
}

// A mesh no CAD program wrote: every vertex moved by noise of 0.1 % of the part's size. The
// faces are no longer exact: the construction gives a tree of the part or none (never a wrong
// one), and the mesh fit finishes with the search.
TEST_F(Construction3D, ANoisyMeshStillGivesAValidTree) {
  TriangleMesh mesh = openscad_mesh(
      "difference() { cube([30, 20, 10]); translate([15, 10, -1]) cylinder(r = 5, h = 12, $fn = 48); }");
  rnd::Rng rng(5);
  for (auto& v : mesh.vertices)
    for (double& x : v) x += rnd::uniform(rng, -0.03, 0.03);
  const Construction c = built(mesh);
  if (c.built) EXPECT_GT(iou_against(mesh, c.tree), 0.5);
  FitOptions3D o;
  o.time_limit = 4;
  o.threads = 1;
  const MeshFitResult fit = fit_mesh(mesh, o);
  EXPECT_GT(fit.fit.stats.iou, 0.95);
  EXPECT_GT(iou_against(mesh, fit.fit.tree), 0.9);
}

// With rounded boxes named, a rounded plate is one rounded box read off its four corner arcs,
// not a box with four cylinders at its corners and four planes cutting them.
TEST_F(Construction3D, ARoundedPlateIsOneRoundedBoxWhenRoundedBoxesAreNamed) {
  const TriangleMesh mesh = openscad_mesh(
      "difference() { linear_extrude(4) offset(r = 3, $fn = 32) square([34, 20]);"
      " translate([10, 10, -1]) cylinder(r = 2.5, h = 6, $fn = 32); }");
  ConstructionOptions o;
  o.kinds.add(PrimitiveKind3D::RoundedBox);
  const Construction c = construct_from_surfaces(segment_mesh_surfaces(mesh), o);
  expect_whole(mesh, c, 2);
  EXPECT_EQ(count_leaves(c.tree, [](const Primitive3D& p) { return p.kind == PrimitiveKind3D::RoundedBox; }), 1);
  const Construction plain = built(mesh);
  expect_whole(mesh, plain, 8);
  EXPECT_GT(plain.tree.primitive_count(), 2u);
}

// A rounded block under a thin rounded lid a little smaller (a press-fit peg, a stepped
// plate): with the default kinds each outline is one rounded box, the lid's reaching down
// through the block, not pieces split at the lower corners' axes; and the ledge's samples
// beside the lid's polygonal corners do not stop it.
TEST_F(Construction3D, AStepInARoundedOutlineIsTwoRoundedBoxes) {
  const TriangleMesh mesh = openscad_mesh(
      "linear_extrude(12) offset(r = 1, $fn = 28) square([6, 4], center = true);"
      " translate([0, 0, 12]) linear_extrude(0.3) offset(r = 1, $fn = 28) square([5.75, 3.75], center = true);");
  ConstructionOptions o;
  o.kinds = PrimitiveSet3D::parse(kDefaultMeshPrimitives);
  const Construction c = construct_from_surfaces(segment_mesh_surfaces(mesh), o);
  expect_whole(mesh, c, 3);
  EXPECT_EQ(count_leaves(c.tree, [](const Primitive3D& p) { return p.kind == PrimitiveKind3D::RoundedBox; }), 2);
}

// The mesh fit takes the constructed tree when it explains the mesh, without a search.
TEST_F(Construction3D, TheMeshFitIsTheConstructionWhenItExplainsTheMesh) {
  const TriangleMesh mesh = openscad_mesh(
      "difference() { cube([40, 30, 8]); for (x = [6, 34]) translate([x, 15, -1]) cylinder(r = 2.5, h = 10, $fn = 32);"
      " translate([20, 15, 4]) cube([20, 4, 10], center = true); }");
  const MeshFitResult fit = fitted_by_construction(mesh, 4);
  EXPECT_GT(iou_against(mesh, fit.fit.tree, 128), 0.995);
}

// A ball bored along three axes reaches past the mesh's own box (the bores took its poles):
// measured on a grid that holds the tree, it explains the mesh as its program's four.
TEST_F(Construction3D, ABallBoredAlongThreeAxesIsBuiltAsItsFourPrimitives) {
  const TriangleMesh mesh = openscad_mesh(
      "difference() { sphere(r = 15, $fn = 64); cylinder(r = 5, h = 40, center = true, $fn = 48);"
      " rotate([90, 0, 0]) cylinder(r = 5, h = 40, center = true, $fn = 48);"
      " rotate([0, 90, 0]) cylinder(r = 5, h = 40, center = true, $fn = 48); }");
  const MeshFitResult fit = fitted_by_construction(mesh, 4);
  EXPECT_GT(fit.fit.stats.iou, 0.98);
  EXPECT_GT(iou_against(mesh, fit.fit.tree, 96), 0.98);
}

}  // namespace
}  // namespace csgfit
