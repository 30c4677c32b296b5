#include "csgfit/io/json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "csgfit/error.h"
#include "csgfit/io/image.h"
#include "csgfit/model/frame.h"
#include "random_trees.h"

namespace csgfit {
namespace {

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void expect_near_tree(const Node& a, const Node& b, double tol) {
  ASSERT_EQ(a.kind, b.kind);
  ASSERT_EQ(a.children.size(), b.children.size());
  if (a.is_leaf()) {
    const Primitive& p = a.primitive;
    const Primitive& q = b.primitive;
    EXPECT_EQ(p.kind, q.kind);
    EXPECT_NEAR(p.cx, q.cx, tol);
    EXPECT_NEAR(p.cy, q.cy, tol);
    EXPECT_NEAR(p.w, q.w, tol);
    EXPECT_NEAR(p.h, q.h, tol);
    EXPECT_NEAR(p.angle, q.angle, tol);
    EXPECT_NEAR(p.apex, q.apex, tol);
  }
  for (std::size_t i = 0; i < a.children.size(); ++i)
    expect_near_tree(a.children[i], b.children[i], tol);
}

FitResult sample_result() {
  FitResult r;
  r.tree = testing::sample_tree();
  r.width = 96;
  r.height = 80;
  r.stats.k = 25;
  r.stats.score = 123.5;
  r.stats.excess = 7;
  r.stats.uncovered = 9;
  r.stats.primitives = r.tree.primitive_count();
  r.stats.iou = 0.9931;
  r.stats.evaluations = 123456;
  r.stats.trees = 4567;
  r.stats.seconds = 1.25;
  r.stats.stop_reason = "converged";
  FitTree alt;
  alt.tree = Node::leaf(Primitive::circle(10, 20, 5));
  alt.stats.iou = 0.5;
  alt.stats.stop_reason = "time";
  r.alternatives.push_back(alt);
  return r;
}

TEST(JsonIo, RoundTripKeepsEverything) {
  const FitResult r = sample_result();
  ModelFrame frame{0.5, 3.0, "part.png"};
  const std::string text = to_json(r, frame);
  ModelFrame back_frame;
  const FitResult back = from_json(text, &back_frame);
  EXPECT_EQ(back.width, 96);
  EXPECT_EQ(back.height, 80);
  EXPECT_DOUBLE_EQ(back_frame.pixel_size, 0.5);
  EXPECT_DOUBLE_EQ(back_frame.thickness, 3.0);
  EXPECT_EQ(back_frame.source, "part.png");
  expect_near_tree(r.tree, back.tree, 1e-9);
  EXPECT_EQ(back.stats.excess, 7u);
  EXPECT_EQ(back.stats.uncovered, 9u);
  EXPECT_EQ(back.stats.primitives, r.stats.primitives);
  EXPECT_EQ(back.stats.evaluations, 123456u);
  EXPECT_EQ(back.stats.trees, 4567u);
  EXPECT_DOUBLE_EQ(back.stats.iou, 0.9931);
  EXPECT_DOUBLE_EQ(back.stats.k, 25);
  EXPECT_DOUBLE_EQ(back.stats.score, 123.5);
  EXPECT_DOUBLE_EQ(back.stats.seconds, 1.25);
  EXPECT_EQ(back.stats.stop_reason, "converged");
  ASSERT_EQ(back.alternatives.size(), 1u);
  expect_near_tree(r.alternatives[0].tree, back.alternatives[0].tree, 1e-9);
  EXPECT_EQ(back.alternatives[0].stats.stop_reason, "time");
}

TEST(JsonIo, WritesModelUnits) {
  FitResult r;
  r.width = r.height = 10;
  r.tree = Node::leaf(Primitive::circle(4, 6, 2));
  const std::string text = to_json(r, ModelFrame{0.5, 0, ""});
  EXPECT_NE(text.find("\"schema\": \"csgfit/1\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"r\": 1.0"), std::string::npos) << text;
  EXPECT_NE(text.find("\"cx\": 2.0"), std::string::npos) << text;
  EXPECT_NE(text.find("\"cy\": 3.0"), std::string::npos) << text;
  EXPECT_NE(text.find("\"units\": \"mm\""), std::string::npos) << text;
}

TEST(JsonIo, SharedDimensionsAreWrittenBesideTheTreeInModelUnits) {
  FitResult r;
  r.width = 40;
  r.height = 20;
  r.tree = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(20, 10, 36, 16)),
                                           Node::leaf(Primitive::circle(8, 10, 3)),
                                           Node::leaf(Primitive::circle(32, 10, 3))});
  const std::string text = to_json(r, ModelFrame{0.5, 0, ""});
  const std::string expected = R"("shared_dimensions": [
    {
      "name": "hole_r",
      "value": 1.5,
      "uses": [
        {
          "leaf": 1,
          "field": "r"
        },
        {
          "leaf": 2,
          "field": "r"
        }
      ]
    }
  ])";
  EXPECT_NE(text.find(expected), std::string::npos) << text;
  // Derived from the values: reading it back changes nothing.
  expect_near_tree(r.tree, from_json(text).tree, 1e-12);
}

TEST(JsonIo, RandomTreesRoundTrip) {
  std::mt19937_64 rng(42);
  for (int i = 0; i < 200; ++i) {
    FitResult r;
    r.width = 128;
    r.height = 96;
    r.tree = testing::random_tree(rng, r.width, r.height, 4);
    const double pixel_size = std::uniform_real_distribution<double>(0.01, 3.0)(rng);
    const FitResult back = from_json(to_json(r, ModelFrame{pixel_size, 0, "x"}));
    expect_near_tree(r.tree, back.tree, 1e-9);
  }
}

TEST(JsonIo, NonFiniteParameterThrows) {
  FitResult r;
  r.width = r.height = 10;
  Primitive p = Primitive::rectangle(5, 5, 2, 2);
  p.cx = std::numeric_limits<double>::quiet_NaN();
  r.tree = Node::op(NodeKind::Union, {Node::leaf(Primitive::circle(1, 1, 1)), Node::leaf(p)});
  try {
    to_json(r, ModelFrame{});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tree.children[1]"), std::string::npos) << e.what();
  }
}

TEST(JsonIo, MalformedInputGivesOneLineErrors) {
  const char* bad[] = {
      "",
      "{",
      "[1, 2]",
      "{\"schema\": \"csgfit/2\", \"tree\": {\"type\": \"circle\", \"cx\": 0, \"cy\": 0, \"r\": 1}}",
      "{\"schema\": \"csgfit/1\"}",
      "{\"schema\": \"csgfit/1\", \"canvas\": {\"width_px\": 10, \"height_px\": 10, "
      "\"pixel_size\": 0}, \"tree\": {\"type\": \"circle\", \"cx\": 0, \"cy\": 0, \"r\": 1}}",
      "{\"type\": \"circle\", \"cx\": 0, \"cy\": 0}",
      "{\"type\": \"circle\", \"cx\": 0, \"cy\": 0, \"r\": -1}",
      "{\"type\": \"circle\", \"cx\": \"a\", \"cy\": 0, \"r\": 1}",
      "{\"type\": \"hexagon\", \"cx\": 0, \"cy\": 0}",
      "{\"op\": \"xor\", \"children\": []}",
      "{\"op\": \"union\", \"children\": []}",
      "{\"op\": \"union\"}",
      "{\"op\": \"union\", \"children\": [{\"type\": \"rect\", \"cx\": 1, \"cy\": 1, \"w\": 1}]}",
      "{\"type\": \"triangle\", \"points\": [[0, 0], [1, 1], [2, 2]]}",
      "{\"type\": \"triangle\", \"points\": [[0, 0], [1, 1]]}",
      "{\"foo\": 1}",
      "{\"type\": \"circle\", \"cx\": 1e999, \"cy\": 0, \"r\": 1}",
  };
  for (const char* text : bad) {
    try {
      from_json(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      EXPECT_EQ(msg.rfind("JSON: ", 0), 0u) << msg;
    }
  }
  try {
    node_from_json("{\"op\": \"union\", \"children\": [{\"type\": \"rect\", \"cx\": 1, \"cy\": 1, "
                   "\"w\": 1}]}");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tree.children[0] (rect)"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("'h'"), std::string::npos) << e.what();
  }
}

TEST(JsonIo, DeepNestingIsRefused) {
  std::string text;
  for (int i = 0; i < 5000; ++i) text += "{\"op\": \"union\", \"children\": [";
  text += "{\"type\": \"circle\", \"cx\": 0, \"cy\": 0, \"r\": 1}";
  for (int i = 0; i < 5000; ++i) text += "]}";
  EXPECT_THROW(node_from_json(text), InputError);
}

TEST(JsonIo, TrianglePointsMatchTheCorners) {
  const Node n = node_from_json(
      "{\"type\": \"triangle\", \"points\": [[10, 10], [30, 12], [18, 40]]}");
  ASSERT_TRUE(n.is_leaf());
  const auto v = n.primitive.triangle_vertices();
  const double want[3][2] = {{10, 10}, {30, 12}, {18, 40}};
  for (const auto& w : want) {
    bool found = false;
    for (const auto& q : v) found = found || (std::hypot(q[0] - w[0], q[1] - w[1]) < 1e-9);
    EXPECT_TRUE(found) << w[0] << "," << w[1];
  }
  // Clockwise input gives the same triangle.
  const Node m = node_from_json(
      "{\"type\": \"triangle\", \"points\": [[18, 40], [30, 12], [10, 10]]}");
  EXPECT_NEAR(m.primitive.area(), n.primitive.area(), 1e-9);
}

TEST(JsonIo, FlipYMirrorsEveryKind) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 50; ++i) {
    const Node tree = testing::random_tree(rng, 64, 48, 3);
    const Bitmap a = render(tree, 64, 48);
    const Bitmap b = render(flip_y(tree, 48), 64, 48);
    std::size_t differ = 0;
    for (int r = 0; r < 48; ++r)
      for (int c = 0; c < 64; ++c) differ += a.get(c, r) != b.get(c, 47 - r);
    // Only pixel centres that lie on a boundary to rounding precision may differ.
    EXPECT_LE(differ, 2u) << structure_string(tree);
    expect_near_tree(flip_y(flip_y(tree, 48), 48), tree, 1e-9);
  }
}

TEST(JsonIo, GroundTruthFilesParse) {
  const std::filesystem::path dir =
      std::filesystem::path(CSGFIT_SOURCE_DIR) / ".." / "shared" / "benchmarks" / "2d";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no benchmarks at " << dir;
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 8 || name.substr(name.size() - 8) != ".gt.json") continue;
    ++files;
    const std::string text = read_text(entry.path());
    Node n;
    ASSERT_NO_THROW(n = node_from_json(text)) << name;
    EXPECT_GT(n.primitive_count(), 0u) << name;
    const FitResult r = from_json(text);
    EXPECT_EQ(r.tree, n) << name;
    // The ground truth is in image coordinates (y down) on 128 x 128 canvases: mirrored into
    // the solver's frame it must draw the benchmark image.
    const std::filesystem::path png = dir / (name.substr(0, name.size() - 8) + ".png");
    if (std::filesystem::exists(png)) {
      const Bitmap target = read_bitmap(png.string());
      const Bitmap drawn = render(flip_y(n, target.height()), target.width(), target.height());
      EXPECT_GE(iou(drawn, target), 0.999) << name;
    }
  }
  EXPECT_GT(files, 0);
}

}  // namespace
}  // namespace csgfit
