// Reading 3D documents back (csgfit export): what to_json3d writes, from_json3d reads as the
// same tree; bad documents are one-line InputErrors.
#include <gtest/gtest.h>

#include <string>

#include "csgfit/error.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/io/json.h"

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

}  // namespace
}  // namespace csgfit
