// The .csg reader: OpenSCAD's own output for each construct, the errors, and the limits.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/io/openscad_csg.h"
#include "scratch_dir.h"

namespace csgfit {
namespace {

bool have_openscad() {
  static const bool found = std::system("command -v openscad >/dev/null 2>&1") == 0;
  return found;
}

#define REQUIRE_OPENSCAD() \
  if (!have_openscad()) GTEST_SKIP() << "openscad is not on PATH"

std::vector<double> numbers(const ScadValue& v) {
  std::vector<double> out;
  for (const ScadValue& x : v.items) out.push_back(x.number);
  return out;
}

// The message of the InputError that parsing `text` throws ("" when it parses).
std::string parse_error(const std::string& text) {
  try {
    parse_openscad_csg(text, "t.csg");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class OpenScadCsgTest : public testing::ScratchDirTest {
 protected:
  // OpenSCAD's .csg for the .scad text `scad`, parsed; text_ keeps the .csg.
  std::vector<ScadCall> flatten(const std::string& scad) {
    text_ = flatten_scad_with_openscad(file("in.scad", scad));
    return parse_openscad_csg(text_, "in.csg");
  }
  std::string text_;
};

TEST_F(OpenScadCsgTest, BooleansAndGroup) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten(
      "union() { cube(1); sphere(1); }\n"
      "difference() { cube(2); cube(1); }\n"
      "intersection() { cube(2); sphere(1.5); }\n"
      "group() { cube(1); }\n");
  ASSERT_EQ(calls.size(), 4u);
  EXPECT_EQ(calls[0].name, "union");
  EXPECT_EQ(calls[0].children.size(), 2u);
  EXPECT_EQ(calls[0].children[1].name, "sphere");
  EXPECT_EQ(calls[1].name, "difference");
  EXPECT_EQ(calls[2].name, "intersection");
  EXPECT_EQ(calls[3].name, "group");
  EXPECT_EQ(calls[0].line, 1u);
  EXPECT_EQ(text_.substr(calls[0].source_begin, 7), "union()");
  EXPECT_EQ(text_[calls[0].source_end - 1], '}');
}

TEST_F(OpenScadCsgTest, TransformsBecomeMultmatrix) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten(
      "translate([1, 2, 3]) rotate([0, 0, 90]) scale([2, 3, 4]) mirror([1, 0, 0]) cube(1);");
  ASSERT_EQ(calls.size(), 1u);
  const ScadCall* c = &calls[0];
  std::vector<const ScadCall*> chain;
  while (c->name == "multmatrix") {
    chain.push_back(c);
    ASSERT_EQ(c->children.size(), 1u);
    c = &c->children[0];
  }
  ASSERT_EQ(chain.size(), 4u);
  EXPECT_EQ(c->name, "cube");
  const ScadValue& m = chain[0]->arguments.at(0).second;
  EXPECT_EQ(chain[0]->arguments.at(0).first, "");  // the matrix is positional
  ASSERT_TRUE(m.is_vector());
  ASSERT_EQ(m.items.size(), 4u);
  EXPECT_EQ(numbers(m.items[0]), (std::vector<double>{1, 0, 0, 1}));
  EXPECT_EQ(numbers(m.items[1]), (std::vector<double>{0, 1, 0, 2}));
  EXPECT_EQ(numbers(m.items[2]), (std::vector<double>{0, 0, 1, 3}));
  EXPECT_EQ(numbers(m.items[3]), (std::vector<double>{0, 0, 0, 1}));
  const ScadValue& scale = chain[2]->arguments.at(0).second;
  EXPECT_EQ(numbers(scale.items[1]), (std::vector<double>{0, 3, 0, 0}));
  EXPECT_EQ(numbers(chain[3]->arguments.at(0).second.items[0]), (std::vector<double>{-1, 0, 0, 0}));
  EXPECT_NEAR(chain[1]->arguments.at(0).second.items[1].items[0].number, 1.0, 1e-9);
}

TEST_F(OpenScadCsgTest, Primitives3d) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten(
      "cube([1, 2, 1e-5], center = true);\n"
      "sphere(r = 2, $fn = 8);\n"
      "cylinder(h = 3, r1 = 1, r2 = 0.5, center = true);\n"
      "cube(-0);\n");
  ASSERT_EQ(calls.size(), 4u);
  EXPECT_EQ(numbers(*calls[0].argument("size")), (std::vector<double>{1, 2, 1e-5}));
  EXPECT_TRUE(calls[0].argument("center")->boolean);
  EXPECT_EQ(calls[1].argument("r")->number, 2);
  EXPECT_EQ(calls[1].argument("$fn")->number, 8);
  EXPECT_EQ(calls[1].argument("$fa")->number, 12);
  const ScadCall& cyl = calls[2];
  EXPECT_EQ(cyl.argument("h")->number, 3);
  EXPECT_EQ(cyl.argument("r1")->number, 1);
  EXPECT_EQ(cyl.argument("r2")->number, 0.5);
  ASSERT_TRUE(cyl.argument("center")->is_bool());
  EXPECT_TRUE(cyl.argument("center")->boolean);
  EXPECT_EQ(cyl.argument("r"), nullptr);
  EXPECT_TRUE(std::signbit(calls[3].argument("size")->items[0].number));
}

TEST_F(OpenScadCsgTest, Shapes2dAndExtrusions) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten(
      "linear_extrude(height = 2, center = true, twist = 30, scale = 0.5, slices = 4) circle(r = 1);\n"
      "rotate_extrude(angle = 90) translate([2, 0]) square([1, 2], center = true);\n"
      "linear_extrude(1) polygon(points = [[0, 0], [1, 0], [0, 1]], paths = [[0, 1, 2]]);\n");
  ASSERT_EQ(calls.size(), 3u);
  const ScadCall& lin = calls[0];
  EXPECT_EQ(lin.name, "linear_extrude");
  EXPECT_EQ(lin.argument("height")->number, 2);
  EXPECT_TRUE(lin.argument("center")->boolean);
  EXPECT_EQ(lin.argument("twist")->number, 30);
  EXPECT_EQ(lin.argument("slices")->number, 4);
  EXPECT_EQ(numbers(*lin.argument("scale")), (std::vector<double>{0.5, 0.5}));
  EXPECT_EQ(lin.children.at(0).name, "circle");
  EXPECT_EQ(lin.children.at(0).argument("r")->number, 1);
  const ScadCall& rot = calls[1];
  EXPECT_EQ(rot.argument("angle")->number, 90);
  const ScadCall& sq = rot.children.at(0).children.at(0);
  EXPECT_EQ(sq.name, "square");
  EXPECT_EQ(numbers(*sq.argument("size")), (std::vector<double>{1, 2}));
  const ScadCall& poly = calls[2].children.at(0);
  EXPECT_EQ(poly.name, "polygon");
  const ScadValue& pts = *poly.argument("points");
  ASSERT_EQ(pts.items.size(), 3u);
  EXPECT_EQ(numbers(pts.items[1]), (std::vector<double>{1, 0}));
  EXPECT_EQ(numbers(poly.argument("paths")->items.at(0)), (std::vector<double>{0, 1, 2}));
}

TEST_F(OpenScadCsgTest, ColorAndRender) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten("color(\"red\", 0.5) cube(1);\nrender(convexity = 2) cube(1);\n");
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls[0].name, "color");
  EXPECT_EQ(numbers(calls[0].arguments.at(0).second), (std::vector<double>{1, 0, 0, 0.5}));
  EXPECT_EQ(calls[1].name, "render");
  EXPECT_EQ(calls[1].argument("convexity")->number, 2);
  EXPECT_EQ(calls[1].children.at(0).name, "cube");
}

TEST_F(OpenScadCsgTest, OpaqueCallsKeepTheirText) {
  REQUIRE_OPENSCAD();
  const auto calls = flatten(
      "hull() { cube(1); translate([2, 0, 0]) sphere(1); }\n"
      "minkowski() { cube(1); sphere(0.1); }\n"
      "polyhedron(points = [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "
      "faces = [[0,1,2],[0,3,1],[0,2,3],[1,3,2]]);\n"
      "linear_extrude(1) text(\"Hi\", size = 3);\n"
      "linear_extrude(1) offset(r = 0.5) square(1);\n"
      "projection(cut = true) cube(1);\n"
      "surface(file = \"h.dat\");\n"
      "import(\"m.stl\");\n");
  ASSERT_EQ(calls.size(), 8u);
  std::vector<std::string> names;
  for (const ScadCall& c : calls) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"hull", "minkowski", "polyhedron", "linear_extrude",
                                             "linear_extrude", "projection", "surface", "import"}));
  EXPECT_EQ(calls[3].children.at(0).name, "text");
  EXPECT_EQ(calls[3].children.at(0).argument("text")->text, "Hi");
  EXPECT_EQ(calls[4].children.at(0).name, "offset");
  EXPECT_EQ(calls[6].argument("file")->text, "h.dat");
  EXPECT_EQ(calls[7].argument("file")->text, "m.stl");
  EXPECT_EQ(calls[2].argument("faces")->items.size(), 4u);

  const ScadCall& hull = calls[0];
  const std::string hull_text = text_.substr(hull.source_begin, hull.source_end - hull.source_begin);
  EXPECT_EQ(hull_text.rfind("hull()", 0), 0u);
  EXPECT_EQ(hull_text.back(), '}');
  const auto again = parse_openscad_csg(hull_text, "hull.csg");
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].name, "hull");
  ASSERT_EQ(again[0].children.size(), 2u);
  EXPECT_EQ(again[0].children[1].children.at(0).name, "sphere");
  EXPECT_EQ(again[0].source_begin, 0u);
  EXPECT_EQ(again[0].source_end, hull_text.size());
}

TEST_F(OpenScadCsgTest, InverseCsgBenchmarkSolution) {
  REQUIRE_OPENSCAD();
  const std::string path = "/work/shared/benchmarks/3d/inversecsg/011/inversecsg_solution.scad";
  if (!std::ifstream(path)) GTEST_SKIP() << "no benchmark at " << path;
  const auto calls = parse_openscad_csg(flatten_scad_with_openscad(path), "011.csg");
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0].name, "intersection");
}

TEST(OpenScadCsgParse, ValuesAndSyntax) {
  const auto calls = parse_openscad_csg(
      "// comment\n/* block\n comment */ group();\n"
      "f(1, -2.5e-3, .5, +3, true, false, undef, \"a\\\"b\\\\c\\n\\x41\\u03a9\", [], [1, [2, 3]], $fn = 0);\n"
      "multmatrix([[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]) cube(size = [1, 1, 1]);\n"
      "g() { ; }\n",
      "v.csg");
  ASSERT_EQ(calls.size(), 4u);
  EXPECT_EQ(calls[0].name, "group");
  EXPECT_EQ(calls[0].line, 3u);
  const auto& a = calls[1].arguments;
  ASSERT_EQ(a.size(), 11u);
  EXPECT_EQ(a[0].second.number, 1);
  EXPECT_EQ(a[1].second.number, -2.5e-3);
  EXPECT_EQ(a[2].second.number, 0.5);
  EXPECT_EQ(a[3].second.number, 3);
  EXPECT_TRUE(a[4].second.boolean);
  EXPECT_TRUE(a[5].second.is_bool() && !a[5].second.boolean);
  EXPECT_TRUE(a[6].second.is_undef());
  EXPECT_EQ(a[7].second.text, "a\"b\\c\nA\xce\xa9");
  EXPECT_TRUE(a[8].second.is_vector() && a[8].second.items.empty());
  EXPECT_EQ(a[9].second.items.at(1).items.at(1).number, 3);
  EXPECT_EQ(a[10].first, "$fn");
  EXPECT_EQ(calls[2].children.at(0).name, "cube");  // a child without braces
  EXPECT_EQ(calls[2].source_end, calls[2].children[0].source_end);
  EXPECT_TRUE(calls[3].children.empty());
}

// OpenSCAD 2021 writes text() strings without escaping them.
TEST(OpenScadCsgParse, UnescapedTextOfOpenScad2021) {
  const auto calls = parse_openscad_csg("text(text = \"a\"b\\c\td\", size = 3);", "t.csg");
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0].argument("text")->text, "a\"b\\c\td");
  EXPECT_EQ(calls[0].argument("size")->number, 3);
}

TEST(OpenScadCsgParse, Errors) {
  EXPECT_EQ(parse_error("cube(size = [1, 1, 1], cen"),
            "t.csg:1: the file ends inside the arguments of cube() from line 1 (it is truncated)");
  EXPECT_NE(parse_error("union() {\n cube(1);\n").find("t.csg:3: the file ends inside union() from line 1"),
            std::string::npos);
  EXPECT_EQ(parse_error("cube(1);\n}"), "t.csg:2: a '}' without an open '{'");
  EXPECT_NE(parse_error("union() { cube(1) }").find("expected"), std::string::npos);
  EXPECT_NE(parse_error("sphere(r = -nan);").find("t.csg:1: the number '-nan' is not finite"),
            std::string::npos);
  EXPECT_NE(parse_error("cube(size = [inf, 1, 1]);").find("not finite"), std::string::npos);
  EXPECT_NE(parse_error("cube(size = 1e999);").find("out of the range"), std::string::npos);
  EXPECT_EQ(parse_error("cube(size = @);"), "t.csg:1: unexpected character '@'");
  EXPECT_NE(parse_error("cube(size = 1..2);").find("bad number"), std::string::npos);
  EXPECT_NE(parse_error("cube(size = [0:2]);").find("unexpected character ':'"), std::string::npos);
  EXPECT_NE(parse_error("cube(foo);").find("'=' after an argument name"), std::string::npos);
  EXPECT_NE(parse_error("x = 1;").find("'(' after a module name"), std::string::npos);
  EXPECT_NE(parse_error("cube(size = \"abc);").find("never closed"), std::string::npos);
  EXPECT_NE(parse_error("/* cube(1);").find("t.csg:1: a /* comment is never closed"), std::string::npos);
  EXPECT_NE(parse_error("\n%cube(1);").find("t.csg:2: the background modifier '%'"), std::string::npos);
  EXPECT_NE(parse_error("#cube(1);").find("debug modifier"), std::string::npos);
  EXPECT_NE(parse_error("multmatrix(1)").find("ends inside multmatrix()"), std::string::npos);
  EXPECT_EQ(parse_error(""), "");
}

TEST(OpenScadCsgParse, DeepNestingIsRefused) {
  const int n = 100000;
  std::string calls;
  for (int i = 0; i < n; ++i) calls += "group() {";
  calls += "cube(1);";
  for (int i = 0; i < n; ++i) calls += "}";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(parse_error(calls), "t.csg:1: calls nested deeper than 4096 levels (the reader's max_depth)");
  const std::string vectors = "f(" + std::string(n, '[') + std::string(n, ']') + ");";
  EXPECT_EQ(parse_error(vectors), "t.csg:1: vectors nested deeper than 4096 levels (the reader's max_depth)");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));

  std::string at_limit;  // exactly max_depth levels parse
  for (int i = 0; i < 4095; ++i) at_limit += "group() {\n";
  at_limit += "cube(1);";
  for (int i = 0; i < 4095; ++i) at_limit += "}";
  EXPECT_EQ(parse_error(at_limit), "");
}

TEST(OpenScadCsgParse, MillionSiblings) {
  const std::string one = "cube(size=[1,1,1], center=false);\n";
  std::string text;
  text.reserve(one.size() * 1000000);
  for (int i = 0; i < 1000000; ++i) text += one;
  const auto calls = parse_openscad_csg(text, "big.csg");
  ASSERT_EQ(calls.size(), 1000000u);
  EXPECT_EQ(calls.back().line, 1000000u);
  EXPECT_EQ(calls.back().source_end, text.size() - 1);
}

TEST_F(OpenScadCsgTest, ScadOpenScadCannotParse) {
  REQUIRE_OPENSCAD();
  try {
    flatten_scad_with_openscad(file("bad.scad", "cube(1;\n"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("OpenSCAD cannot flatten"), std::string::npos) << m;
    EXPECT_NE(m.find("syntax error"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST_F(OpenScadCsgTest, MissingFileAndMissingOpenScad) {
  EXPECT_THROW(flatten_scad_with_openscad(dir_ + "/none.scad"), InputError);
  const std::string scad = file("a.scad", "cube(1);");
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  ::setenv("PATH", dir_.c_str(), 1);
  std::string message;
  try {
    flatten_scad_with_openscad(scad);
  } catch (const InputError& e) {
    message = e.what();
  }
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_NE(message.find("'openscad' is not on PATH"), std::string::npos) << message;
}

}  // namespace
}  // namespace csgfit
