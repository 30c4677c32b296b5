// OpenSCAD programs as the optimiser reads and writes them: every halfspace's inside test
// agrees with the primitive OpenSCAD means, placements fold into leaves, what we write reads
// back to the same leaves, and bad programs are refused in one line.
#include <gtest/gtest.h>

#include <cmath>

#include "csgfit/error.h"
#include "csgfit/io/openscad_program.h"

namespace csgfit {
namespace {

ScadProgram program(const std::string& text) { return program_from_csg(parse_openscad_csg(text, "t.csg"), text, "t.csg"); }

bool inside3(const ScadProgram& p, int leaf, double x, double y, double z) {
  const auto& h = p.halfspaces3.at(static_cast<std::size_t>(leaf));
  return h.bounds.contains({x, y, z}) && h.contains({x, y, z});
}

TEST(OpenScadProgram, PrimitivesUnderTheirMatrices) {
  const ScadProgram p = program(
      "multmatrix([[1, 0, 0, 10], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) {\n"
      "  cube(size = [2, 4, 6], center = false);\n"
      "  sphere($fn = 0, $fa = 12, $fs = 2, r = 3);\n"
      "}\n"
      "cylinder($fn = 0, $fa = 12, $fs = 2, h = 10, r1 = 2, r2 = 0, center = true);\n");
  ASSERT_EQ(p.dimension, 3);
  ASSERT_EQ(p.halfspaces3.size(), 3u);
  EXPECT_TRUE(inside3(p, 0, 11, 3.9, 5.9));
  EXPECT_FALSE(inside3(p, 0, 9.9, 1, 1));
  EXPECT_TRUE(inside3(p, 1, 12.9, 0, 0));
  EXPECT_FALSE(inside3(p, 1, 7, 0, 0.5));
  EXPECT_TRUE(inside3(p, 2, 1.9, 0, -4.9));  // the wide end at the bottom
  EXPECT_FALSE(inside3(p, 2, 0.5, 0, 4.9));   // the apex at the top
  EXPECT_EQ(to_text(p.tree), "union(union(h0, h1), h2)");
  EXPECT_EQ(p.leaves[0].call, "cube(size = [2, 4, 6], center = false);");
}

TEST(OpenScadProgram, ExtrusionsOfTwoDimensionalTrees) {
  const ScadProgram p = program(
      "linear_extrude(height = 10, center = false, convexity = 1, twist = 90, slices = 10, scale = 1) {\n"
      "  difference() { square(size = [4, 2], center = true); circle($fn = 0, $fa = 12, $fs = 2, r = 0.5); }\n"
      "}\n"
      "rotate_extrude(angle = 180, convexity = 1) { multmatrix([[1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) "
      "circle($fn = 0, $fa = 12, $fs = 2, r = 1); }\n");
  ASSERT_EQ(p.halfspaces3.size(), 2u);
  EXPECT_TRUE(inside3(p, 0, 1.5, 0, 0.01));   // the bar along x at the bottom
  EXPECT_FALSE(inside3(p, 0, 1.5, 0, 9.99));  // turned by 90 degrees at the top: along y
  EXPECT_TRUE(inside3(p, 0, 0, 1.5, 9.99));
  EXPECT_FALSE(inside3(p, 0, 0, 0, 5));       // the hole
  EXPECT_TRUE(inside3(p, 1, 0, 5, 0));        // the half torus: y > 0 only
  EXPECT_FALSE(inside3(p, 1, 0, -5, 0));
}

TEST(OpenScadProgram, OpaqueCallsAreKeptVerbatim) {
  const std::string hull = "hull() {\n  cube(size = [1, 1, 1], center = false);\n  sphere(r = 1);\n}";
  const ScadProgram p = program("difference() {\n" + hull + "\n cube(size = [0.5, 0.5, 3], center = true);\n}\n");
  ASSERT_EQ(p.opaque.size(), 1u);
  EXPECT_EQ(p.opaque[0].call, hull);
  EXPECT_EQ(to_text(p.tree), "diff(opaque0, h0)");
  const std::string out = write_openscad_program(p, p.tree, {});
  EXPECT_NE(out.find(hull.substr(0, 8)), std::string::npos);
  const ScadProgram again = program(out);
  EXPECT_EQ(again.opaque.size(), 1u);
  EXPECT_EQ(to_text(again.tree), "diff(opaque0, h0)");
}

TEST(OpenScadProgram, WrittenPlacementsReadBackToTheSameMatrices) {
  const ScadProgram p = program(
      "multmatrix([[0.866025, -0.5, 0, 1], [0.5, 0.866025, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]) "
      "multmatrix([[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) sphere(r = 1);\n"
      "multmatrix([[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(size = [1, 1, 1], center = false);\n");
  for (bool csg : {false, true}) {
    ScadWriteOptions o;
    o.csg_style = csg;
    const std::string text = write_openscad_program(p, p.tree, o);
    EXPECT_EQ(text.find("multmatrix") != std::string::npos, true) << "the sheared cube needs it";
    if (!csg) EXPECT_NE(text.find("rotate("), std::string::npos) << text;
    const ScadProgram q = program(text);
    ASSERT_EQ(q.leaves.size(), 2u);
    for (std::size_t l = 0; l < 2; ++l)
      for (int i = 0; i < 16; ++i) EXPECT_NEAR(q.leaves[l].matrix[i], p.leaves[l].matrix[i], 1e-6) << text;
  }
}

TEST(OpenScadProgram, BadProgramsAreRefused) {
  EXPECT_THROW(program("multmatrix([[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(size = 1);"),
               InputError);
  EXPECT_THROW(program("cube(size = [1, -1, 1]);"), InputError);
  EXPECT_THROW(program("group();"), InputError);  // no primitive at all
  try {
    program("\n\nsphere(r = 0);");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.csg:3"), std::string::npos) << e.what();
  }
}

TEST(OpenScadProgram, OurPrimitivesForJsonAndStep) {
  const ScadProgram p = program(
      "multmatrix([[1, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(size = [2, 4, 6], center = false);\n"
      "cylinder(h = 4, r1 = 1, r2 = 1, center = false);\n");
  const Node3D tree = node3d_of(p, p.tree);
  ASSERT_EQ(tree.children.size(), 2u);
  const Primitive3D& box = tree.children[0].primitive;
  EXPECT_EQ(box.kind, PrimitiveKind3D::Box);
  EXPECT_NEAR(box.cx, 6, 1e-12);
  EXPECT_NEAR(box.cz, 3, 1e-12);
  const Primitive3D& cyl = tree.children[1].primitive;
  EXPECT_EQ(cyl.kind, PrimitiveKind3D::Cylinder);
  EXPECT_NEAR(cyl.cz, 2, 1e-12);
  const ScadProgram sheared = program("multmatrix([[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(size = 1);");
  EXPECT_THROW(node3d_of(sheared, sheared.tree), InputError);
}

}  // namespace
}  // namespace csgfit
