// Reading 3D documents back (csgfit export): what to_json3d writes, from_json3d reads as the
// same tree; bad documents are one-line InputErrors.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "csgfit/error.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/io/json.h"
#include "sweep_parts.h"

namespace csgfit {
namespace {

Primitive3D polygonal(Primitive3D p, int sides) {
  p.sides = sides;
  return p;
}

// Every kind, and the polygonal cylinder and cone (whose turn about the axis counts).
Node3D every_kind() {
  const Quaternion tilt = Quaternion::from_euler_deg(23, -37, 61);
  return Node3D::op(
      NodeKind::Difference,
      {Node3D::op(NodeKind::Union,
                  {Node3D::leaf(Primitive3D::box(1, 2, 3, 4, 2.5, 1.5, tilt)),
                   Node3D::leaf(Primitive3D::sphere(-1, 0.5, 2, 1.7)),
                   Node3D::leaf(Primitive3D::ellipsoid(1, 1, 1, 2.5, 1.2, 0.8, tilt)),
                   Node3D::leaf(Primitive3D::torus(-2, 0, 1, 2.0, 0.7, tilt))}),
       Node3D::leaf(Primitive3D::cylinder(0, 0, 0, 1.2, 3.5, tilt)),
       Node3D::op(NodeKind::Intersection,
                  {Node3D::leaf(Primitive3D::cone(0, 1, -2, 0, 1.3, 2.2, tilt)),
                   Node3D::leaf(Primitive3D::prism(0.5, -0.5, 1, 3, 2, 1.5, 0.6, tilt))}),
       Node3D::leaf(polygonal(Primitive3D::cylinder(1, 0, 0, 1.2, 3.5, tilt), 6)),
       Node3D::leaf(polygonal(Primitive3D::cone(0, 1, 2, 1.4, 0.3, 2.2, tilt), 1000)),
       Node3D::leaf(Primitive3D::rounded_box(1, 2, 3, 4.1, 2.3, 1.7, 0.37, tilt)),
       Node3D::leaf(Primitive3D::rounded_box(-1, 0, 0.5, 3, 0.7, 1.1, 0.35, tilt))});
}

TEST(Json3D, WhatIsWrittenReadsBackAsTheSameTree) {
  FitResult3D result;
  result.tree = every_kind();
  const VoxelGrid grid(4, 4, 4, 0, 0, 0, 1);
  const std::string text = to_json3d(result, grid, "part.stl");
  ASSERT_TRUE(is_json3d(text));
  std::string source;
  const Node3D back = from_json3d(text, &source);
  EXPECT_EQ(source, "part.stl");
  EXPECT_EQ(structure_string(back), structure_string(result.tree));
  const auto a = leaves(static_cast<const Node3D&>(result.tree));
  const auto b = leaves(back);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // JSON numbers are written with round-trip precision: the same doubles come back, up to
    // the quaternion's renormalisation.
    EXPECT_EQ(a[i]->kind, b[i]->kind);
    EXPECT_DOUBLE_EQ(a[i]->cx, b[i]->cx);
    EXPECT_DOUBLE_EQ(a[i]->cz, b[i]->cz);
    for (int d = 0; d < 3; ++d) EXPECT_DOUBLE_EQ(a[i]->dims[d], b[i]->dims[d]) << i;
    EXPECT_DOUBLE_EQ(a[i]->apex, b[i]->apex);
    EXPECT_EQ(a[i]->sides, b[i]->sides) << i;
    EXPECT_DOUBLE_EQ(a[i]->corner, b[i]->corner) << i;
    EXPECT_NEAR(a[i]->rotation.w, b[i]->rotation.w, 1e-15);
    EXPECT_NEAR(a[i]->rotation.x, b[i]->rotation.x, 1e-15);
    EXPECT_NEAR(a[i]->rotation.z, b[i]->rotation.z, 1e-15);
    EXPECT_DOUBLE_EQ(a[i]->volume(), b[i]->volume());
  }
}

TEST(Json3D, TwoDimensionalAndBadDocumentsAreRefused) {
  EXPECT_FALSE(is_json3d(R"({"schema": "csgfit/1", "dimension": 2})"));
  EXPECT_FALSE(is_json3d("not json"));
  const std::string head = R"({"schema": "csgfit/1", "dimension": 3, "units": "mm", "tree": )";
  for (const std::string& tree :
       {std::string(R"({"type": "box", "center": [0, 0, 0], "size": [1, -1, 1]})"),
        std::string(R"({"type": "blob", "center": [0, 0, 0]})"),
        std::string(R"({"type": "sphere", "r": 1})"),
        std::string(R"({"type": "sphere", "center": [0, 0, 0], "r": 1, "rotation": [0, 0, 0, 0]})"),
        std::string(R"({"op": "union", "children": []})"),
        std::string(R"({"op": "xor", "children": [{"type": "sphere", "center": [0, 0, 0], "r": 1}]})")}) {
    try {
      from_json3d(head + tree + "}");
      ADD_FAILURE() << "accepted " << tree;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW(from_json3d(R"({"schema": "csgfit/1", "dimension": 2, "tree": {}})"), InputError);
}

// every_kind() as the 3D document.
std::string every_kind_text() {
  FitResult3D result;
  result.tree = every_kind();
  return to_json3d(result, VoxelGrid(4, 4, 4, 0, 0, 0, 1), "part.stl");
}

// A 3D document up to its one leaf's type.
const char* const kLeafHead =
    R"({"schema": "csgfit/1", "dimension": 3, "units": "mm", "tree": {"type": )";

// Reading `text` fails with one line that names `field`.
void expect_refused(const std::string& text, const std::string& field) {
  try {
    from_json3d(text);
    ADD_FAILURE() << "accepted " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

// "sides" is written for polygonal cylinders and cones only, and read back only as an integer
// from 3 to 1000 on one of them.
TEST(Json3D, SidesAreWrittenWhenPolygonalAndCheckedWhenRead) {
  const std::string text = every_kind_text();
  EXPECT_NE(text.find("\"sides\": 6"), std::string::npos);
  EXPECT_NE(text.find("\"sides\": 1000"), std::string::npos);
  EXPECT_EQ(text.find("\"sides\": 0"), std::string::npos);
  const std::string head = kLeafHead;
  const std::string cylinder = R"("cylinder", "center": [0, 0, 0], "r": 1, "h": 2, "sides": )";
  const std::string cone = R"("cone", "center": [0, 0, 0], "r1": 1, "r2": 0, "h": 2, "sides": )";
  const std::string box = R"("box", "center": [0, 0, 0], "size": [1, 1, 1], "sides": )";
  EXPECT_EQ(from_json3d(head + cylinder + "3}}").primitive.sides, 3);
  EXPECT_EQ(from_json3d(head + cone + "5}}").primitive.sides, 5);
  for (const std::string& tree : {cylinder + "2}", cylinder + "1001}", cylinder + "6.5}",
                                  cylinder + "-6}", cylinder + "\"6\"}", cylinder + "null}",
                                  box + "6}"})
    expect_refused(head + tree + "}", "sides");
}

// A rounded box is "size" and "corner" (and never "sides"); the corner is read back only in
// (0, min(sx, sy) / 2], a stadium's as written in decimal included.
TEST(Json3D, ARoundedBoxsCornerIsWrittenAndCheckedWhenRead) {
  const std::string text = every_kind_text();
  EXPECT_NE(text.find("\"type\": \"rounded_box\""), std::string::npos);
  EXPECT_NE(text.find("\"corner\": 0.37"), std::string::npos);
  EXPECT_EQ(text.find("\"corner\": 0,"), std::string::npos) << "no corner on other kinds";
  const std::string head = kLeafHead;
  const std::string rounded = R"("rounded-box", "center": [0, 0, 0], "size": [20, 10, 4], )";
  const Primitive3D p = from_json3d(head + rounded + R"("corner": 3}})").primitive;
  EXPECT_EQ(p.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_EQ(p.corner, 3);
  EXPECT_EQ(from_json3d(head + rounded + R"("corner": 5}})").primitive.corner, 5);
  // A stadium's 1/3 written with 17 digits, a hair over the bound.
  const std::string thin = R"("rounded_box", "center": [0, 0, 0], "size": [0.66666666666666674, 1, 1], )";
  EXPECT_DOUBLE_EQ(from_json3d(head + thin + R"("corner": 0.33333333333333343}})").primitive.corner,
                   0.66666666666666674 / 2);
  for (const std::string& tree :
       {rounded + R"("corner": 0})", rounded + R"("corner": -1})", rounded + R"("corner": 5.01})",
        rounded + R"("corner": "3"})", rounded + R"("corner": null})", rounded + R"("h": 4})",
        std::string(R"("box", "center": [0, 0, 0], "size": [1, 1, 1], "corner": 0.2})")})
    expect_refused(head + tree + "}", "corner");
  expect_refused(head + rounded + R"("corner": 3, "sides": 8}})", "sides");
}

std::string document(const Node3D& tree) {
  FitResult3D result;
  result.tree = tree;
  return to_json3d(result, VoxelGrid(4, 4, 4, 0, 0, 0, 1), "part.stl");
}

// "sweeps" gives a reader that draws extrusions (the FreeCAD builder) each sweep's node,
// frame and its leaves' sections as 2D shapes; a tree without one has no "sweeps".
TEST(Json3D, SweepsCarryTheirFrameAndSections) {
  using nlohmann::json;
  EXPECT_FALSE(json::parse(document(every_kind())).contains("sweeps"));
  const json plate = json::parse(document(testing::plate_with_holes()))["sweeps"];
  ASSERT_EQ(plate.size(), 1u);
  EXPECT_EQ(plate[0]["node"], 0);
  EXPECT_EQ(plate[0]["kind"], "linear_extrude");
  EXPECT_EQ(plate[0]["center"], json::parse("[0, 0, 8]"));
  EXPECT_EQ(plate[0]["rotation"], json::parse("[1, 0, 0, 0]"));
  EXPECT_EQ(plate[0]["height"], 4.0);
  EXPECT_EQ(plate[0]["sections"][0],
            json::parse(R"({"leaf": 0, "type": "rectangle", "cx": 16, "cy": 16, "w": 26, "h": 18,
                            "angle": 0})"));
  EXPECT_EQ(plate[0]["sections"][1],
            json::parse(R"({"leaf": 1, "type": "circle", "cx": 8, "cy": 11, "r": 2.5})"));
  EXPECT_EQ(plate[0]["sections"][3]["sides"], 6);
  EXPECT_NEAR(plate[0]["sections"][3]["angle"].get<double>(), 10, 1e-9);

  // A rounded box's section is its rounded rectangle, sides as the plane sees them.
  const json rounded = json::parse(document(testing::rounded_plate_with_slot()))["sweeps"][0];
  EXPECT_EQ(rounded["height"], 4.0);
  json plate_section = rounded["sections"][0];
  EXPECT_NEAR(plate_section["angle"].get<double>(), 0, 1e-9);
  plate_section.erase("angle");
  EXPECT_EQ(plate_section, json::parse(R"({"leaf": 0, "type": "rounded_rectangle", "cx": 16,
                                           "cy": 16, "w": 26, "h": 18, "r": 4})"));
  EXPECT_EQ(rounded["sections"][2]["type"], "rounded_rectangle");
  EXPECT_EQ(rounded["sections"][2]["r"], 1.5);
  EXPECT_NEAR(rounded["sections"][2]["angle"].get<double>(), 30, 1e-9);

  const json turned = json::parse(document(testing::turned_part()))["sweeps"][0];
  EXPECT_EQ(turned["kind"], "rotate_extrude");
  EXPECT_FALSE(turned.contains("height"));
  EXPECT_EQ(turned["center"], json::parse("[16, 16, 0]"));
  EXPECT_EQ(turned["sections"][0],
            json::parse(R"({"leaf": 0, "type": "rectangle", "cx": 4.5, "cy": 16, "w": 9, "h": 12,
                            "angle": 0})"));
  EXPECT_EQ(turned["sections"][2],
            json::parse(R"({"leaf": 2, "type": "circle", "cx": 9, "cy": 16, "r": 2})"));

  // A prism seen from behind is its triangle turned half round, apex on the other side; a
  // pointed cone's profile is a triangle; a sphere's the half disc on the axis's side.
  const Quaternion upside_down = Quaternion::from_euler_deg(180, 0, 0);
  const json prism = json::parse(document(Node3D::op(
      NodeKind::Union, {Node3D::leaf(Primitive3D::box(0, 0, 0, 4, 4, 2)),
                        Node3D::leaf(Primitive3D::prism(3, 0, 0, 2, 3, 2, 0.5, upside_down))})));
  const json triangle = prism["sweeps"][0]["sections"][1];
  EXPECT_EQ(triangle["type"], "triangle");
  EXPECT_NEAR(triangle["angle"].get<double>(), 180, 1e-9);
  EXPECT_EQ(triangle["apex"], -0.5);
  const json shaft = json::parse(document(Node3D::op(
      NodeKind::Union, {Node3D::leaf(Primitive3D::cone(0, 0, 1, 2, 0, 2)),
                        Node3D::leaf(Primitive3D::sphere(0, 0, -1, 1))})))["sweeps"][0];
  EXPECT_EQ(shaft["sections"][0]["points"], json::parse("[[0, 0], [2, 0], [0, 2]]"));
  EXPECT_EQ(shaft["sections"][1],
            json::parse(R"({"leaf": 1, "type": "half_disc", "cx": 0, "cy": -1, "r": 1})"));
}

}  // namespace
}  // namespace csgfit
