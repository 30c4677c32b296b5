// The 3D .scad writer's sweeps: a subtree that is a profile swept along an axis is written as
// linear_extrude of its leaves' sections, one turned about an axis as rotate_extrude, each leaf
// keeping its tab; a tree with no sweep is written as before. And (when CSGFIT_SCAD3D_DUMP
// names a directory) the files of their OpenSCAD round trip, tests/e2e/scad3d_roundtrip_test.sh.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "csgfit/model/sweeps.h"
#include "random_sweeps.h"
#include "scad_writer3d.h"
#include "sweep_parts.h"
#include "text_checks.h"
#include "voxel_npy.h"

namespace csgfit {
namespace {

using testing::contains;
using testing::lacks;
using testing::occurrences;

TEST(ScadSweeps, PlateWithHolesIsAnExtrudedProfile) {
  const std::string scad = to_scad(testing::plate_with_holes());
  EXPECT_TRUE(contains(scad, "/* [Extrusion 1] */\nextrude_1_z = 8; //")) << scad;
  EXPECT_TRUE(contains(scad, "\nextrude_1_h = 4; //"));
  EXPECT_TRUE(contains(
      scad,
      "module model() {\n"
      "  translate([0, 0, extrude_1_z]) linear_extrude(height = extrude_1_h)\n"
      "    difference() {\n"
      "      translate([box_1_cx, box_1_cy]) square([box_1_size_x, box_1_size_y], center = true);\n"
      "      translate([cyl_2_cx, cyl_2_cy]) circle(r = fn_r(hole_r));\n"
      "      translate([cyl_3_cx, cyl_3_cy]) circle(r = fn_r(hole_r));\n"
      "      translate([cyl_4_cx, cyl_4_cy]) rotate(cyl_4_angle) circle(r = cyl_4_r, $fn = cyl_4_sides);\n"
      "    }\n"
      "}\n"));
  // Each leaf keeps its tab, in the extrusion's plane; the holes' equal radii stay one
  // parameter, their length is the extrusion's height (no hole_h, no box size along z).
  EXPECT_TRUE(contains(scad, "/* [Box 1] */\nbox_1_cx = 16; //"));
  EXPECT_TRUE(contains(scad, "// radius of cylinders 2 and 3\nhole_r = 2.5;"));
  EXPECT_TRUE(contains(scad, "cyl_4_angle = 10; // [-180:0.1:180]"));
  EXPECT_TRUE(contains(scad, "cyl_4_sides = 6; //"));
  for (const char* gone : {"hole_h", "cyl_2_h", "cyl_4_h", "box_1_size_z", "cyl_2_cz", "cube(",
                           "cylinder("})
    EXPECT_TRUE(lacks(scad, gone)) << gone;
}

// A rounded box's section is its offset square, sized by fn_corner as the rounded box is; the
// plate's is drawn with its long side along x (its size_y first), unturned.
TEST(ScadSweeps, RoundedPlateIsAnExtrudedOffsetSquare) {
  const std::string scad = to_scad(testing::rounded_plate_with_slot());
  const std::string corner1 = "fn_corner(rbox_1_corner)", corner3 = "fn_corner(rbox_3_corner)";
  EXPECT_TRUE(contains(
      scad,
      "module model() {\n"
      "  translate([0, 0, extrude_1_z]) linear_extrude(height = extrude_1_h)\n"
      "    difference() {\n"
      "      translate([rbox_1_cx, rbox_1_cy]) offset(r = " + corner1 + ", $fn = corner_fn) "
      "square([rbox_1_size_y - 2 * " + corner1 + ", rbox_1_size_x - 2 * " + corner1 +
      "], center = true);\n"
      "      translate([cyl_2_cx, cyl_2_cy]) circle(r = fn_r(cyl_2_r));\n"
      "      translate([rbox_3_cx, rbox_3_cy]) rotate(rbox_3_angle) offset(r = " + corner3 +
      ", $fn = corner_fn) square([rbox_3_size_x - 2 * " + corner3 + ", rbox_3_size_y - 2 * " +
      corner3 + "], center = true);\n"
      "    }\n"
      "}\n"))
      << scad;
  EXPECT_TRUE(contains(scad, "/* [Rounded box 1] */\nrbox_1_cx = 16; //"));
  EXPECT_TRUE(contains(scad, "rbox_1_size_y = 26; //"));
  EXPECT_TRUE(contains(scad, "rbox_1_corner = 4; //"));
  EXPECT_TRUE(contains(scad, "rbox_3_angle = 30; //"));
  EXPECT_TRUE(contains(scad, "corner_fn = 4 * ceil(segments / 4);"));
  for (const char* gone :
       {"rbox_1_size_z", "rbox_3_size_z", "rbox_1_rot_z", "cyl_2_h", "center = true) offset"})
    EXPECT_TRUE(lacks(scad, gone)) << gone;
}

TEST(ScadSweeps, BracketIsAnUprightProfileExtrudedAlongY) {
  const std::string scad = to_scad(testing::bracket());
  EXPECT_TRUE(contains(scad,
                       "  translate([0, extrude_1_y, 0]) rotate([extrude_1_rot_x, 0, 0]) "
                       "linear_extrude(height = extrude_1_h)\n"
                       "    union() {\n"
                       "      translate([box_1_cx, box_1_cy]) square([box_1_size_x, box_1_size_z], center = true);\n"
                       "      translate([box_2_cx, box_2_cy]) square([box_2_size_x, box_2_size_z], center = true);\n"
                       "    }\n"))
      << scad;
  EXPECT_TRUE(contains(scad, "extrude_1_y = 23; //"));
  EXPECT_TRUE(contains(scad, "extrude_1_rot_x = 90; //"));
  EXPECT_TRUE(contains(scad, "extrude_1_h = 14; //"));
  EXPECT_TRUE(contains(scad, "box_2_cy = 15; //"));  // the wall's middle, up the model's z
}

TEST(ScadSweeps, TurnedPartIsARevolvedHalfProfile) {
  const std::string scad = to_scad(testing::turned_part());
  EXPECT_TRUE(contains(scad,
                       "  translate([revolve_1_x, revolve_1_y, 0]) rotate_extrude() scale([fn_r(1), 1])\n"
                       "    union() {\n"
                       "      difference() {\n"
                       "        translate([0, cyl_1_cz - cyl_1_h / 2]) square([cyl_1_r, cyl_1_h]);\n"
                       "        translate([0, cyl_2_cz - cyl_2_h / 2]) square([cyl_2_r, cyl_2_h]);\n"
                       "      }\n"
                       "      translate([torus_3_major_r, torus_3_cz]) circle(r = fn_r(torus_3_minor_r));\n"
                       "    }\n"))
      << scad;
  EXPECT_TRUE(contains(scad, "/* [Revolution 1] */\nrevolve_1_x = 16; //"));
  EXPECT_TRUE(contains(scad, "// rotate_extrude() sweeps $fn-gons"));
  EXPECT_TRUE(lacks(scad, "csg_torus"));
  EXPECT_TRUE(lacks(scad, "linear_extrude"));
}

// Spheres and cones revolve too: a sphere's profile is the half disc on the axis's side, a
// cone's its quadrilateral (upside down when the cone is), a fat torus's circle is narrowed.
TEST(ScadSweeps, SpheresConesAndFatToriHaveProfilesOffTheAxis) {
  const Node3D knob = Node3D::op(
      NodeKind::Union,
      {Node3D::leaf(Primitive3D::cylinder(5, 5, 2, 3, 4)),
       Node3D::leaf(Primitive3D::cone(5, 5, 6, 3, 1, 4, Quaternion::from_euler_deg(180, 0, 0))),
       Node3D::leaf(Primitive3D::sphere(5, 5, 9, 2)), Node3D::leaf(Primitive3D::torus(5, 5, 0, 3, 2))});
  const std::string scad = to_scad(knob);
  EXPECT_TRUE(contains(scad, "translate([0, cone_2_cz]) polygon([[0, -cone_2_h / 2], [cone_2_r2, "
                             "-cone_2_h / 2], [cone_2_r1, cone_2_h / 2], [0, cone_2_h / 2]]);"))
      << scad;
  EXPECT_TRUE(contains(scad, "translate([0, sphere_3_cz]) csg_half_disc(fn_r(sphere_3_r));"));
  EXPECT_TRUE(contains(scad, "module csg_half_disc(r) intersection() {"));
  EXPECT_TRUE(contains(scad, "scale([min(1, torus_4_major_r / fn_r(torus_4_minor_r)), 1])"));
}

TEST(ScadSweeps, TreesWithoutSweepsAreWrittenAsBefore) {
  const std::string scad = to_scad(testing::steps());
  EXPECT_EQ(occurrences(scad, "cube("), 2u);
  EXPECT_TRUE(lacks(scad, "extrude"));
  EXPECT_TRUE(lacks(scad, "Extrusion"));
  // A sweep inside a tree that is none is written whole, its neighbours as primitives.
  const Node3D part = Node3D::op(
      NodeKind::Union, {testing::plate_with_holes(), Node3D::leaf(Primitive3D::sphere(16, 16, 20, 3))});
  const std::string mixed = to_scad(part);
  EXPECT_EQ(occurrences(mixed, "linear_extrude(height = extrude_1_h)"), 1u);
  EXPECT_TRUE(contains(mixed, "sphere(r = fn_sr(sphere_5_r));"));
  // A morph's two ends are written primitive by primitive: they may sweep apart.
  EXPECT_TRUE(lacks(to_scad_morph(part, part, "b.stl"), "linear_extrude"));
}

// ---------------------------------------------------------------------------------------------
// Files for tests/e2e/scad3d_roundtrip_test.sh: the hand-made parts and random sweeps as .scad
// and the solver's own voxels as .npy, on the grid of ScadWriter3DRoundTrip (64^3 voxels of 0.5
// from the origin). Skipped unless CSGFIT_SCAD3D_DUMP names a directory; the random trees'
// seed changes every run (CSGFIT_TEST_SEED replays one) and is in each file's header.

TEST(ScadSweepRoundTrip, DumpFilesForOpenScad) {
  const char* dir = std::getenv("CSGFIT_SCAD3D_DUMP");
  if (!dir || !*dir) GTEST_SKIP() << "set CSGFIT_SCAD3D_DUMP to a directory to write the files";
  const VoxelGrid frame(64, 64, 64, 0, 0, 0, 0.5);
  const std::uint64_t seed = testing::test_seed();
  std::printf("random sweeps: CSGFIT_TEST_SEED=%llu\n", static_cast<unsigned long long>(seed));
  std::mt19937_64 rng(seed);
  std::vector<Node3D> trees = {testing::plate_with_holes(), testing::bracket(),
                               testing::turned_part(), testing::steps(),
                               testing::rounded_plate_with_slot()};
  while (trees.size() < 17) {
    testing::SweepRegion region;
    region.frame = testing::random_sweep_frame(rng);
    Node3D t = trees.size() % 2 ? testing::random_revolution_tree(rng, region)
                                : testing::random_linear_tree(rng, region);
    // A tree that covers almost nothing would agree trivially.
    if (render(t, frame).count() >= 2000) trees.push_back(std::move(t));
  }
  ScadOptions3D options;
  options.fn = 48;
  for (std::size_t t = 0; t < trees.size(); ++t) {
    const std::string base = std::string(dir) + "/sweep_" + std::to_string(t);
    options.source = "sweep_" + std::to_string(t);
    options.summary = "seed " + std::to_string(seed) + ", " + structure_string(trees[t]);
    const std::string scad = to_scad(trees[t], options);
    // The files test the sweeps: each but the steps must be written as one.
    const bool swept = contains(scad, "linear_extrude(height = extrude_1_h)") ||
                       contains(scad, "rotate_extrude() scale");
    EXPECT_EQ(swept, t != 3) << scad;
    std::ofstream(base + ".scad") << scad;
    testing::write_npy(render(trees[t], frame), base + ".npy");
  }
}

}  // namespace
}  // namespace csgfit
