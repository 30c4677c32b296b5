// OpenSCAD round trip: the .scad the writer produces, rendered by OpenSCAD and sampled at pixel
// centres (scripts/scad_raster.py), must agree with the solver's own raster of the tree.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "csgfit/model/tree2d.h"
#include "csgfit/model/frame.h"
#include "random_trees.h"
#include "scad_writer.h"

namespace csgfit {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 96;
constexpr int kHeight = 80;
constexpr double kPixelSize = 0.5;

bool have_openscad() { return std::system("command -v openscad >/dev/null 2>&1") == 0; }

void write_pbm(const fs::path& path, const Bitmap& b) {
  std::ofstream f(path, std::ios::binary);
  f << "P4\n" << b.width() << " " << b.height() << "\n";
  for (int r = 0; r < b.height(); ++r) {
    std::string row(static_cast<std::size_t>((b.width() + 7) / 8), '\0');
    for (int c = 0; c < b.width(); ++c)
      if (b.get(c, r)) row[static_cast<std::size_t>(c / 8)] |= static_cast<char>(0x80 >> (c % 8));
    f << row;
  }
}

class ScadRoundTrip : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_openscad()) GTEST_SKIP() << "openscad is not installed";
    dir_ = fs::temp_directory_path() /
           ("csgfit_scad_roundtrip_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }

  // Agreement (fraction of pixels) between OpenSCAD's rendering of the exported tree and
  // render(); -1 when the helper failed.
  double agreement(const Node& tree, const std::string& name, double thickness) {
    const fs::path scad = dir_ / (name + ".scad");
    const fs::path ref = dir_ / (name + ".pbm");
    std::ofstream(scad) << to_scad(tree, ModelFrame{kPixelSize, thickness, name + ".png"});
    write_pbm(ref, render(tree, kWidth, kHeight));
    const std::string cmd = "/usr/bin/python3 '" CSGFIT_SOURCE_DIR "/scripts/scad_raster.py' '" +
                            scad.string() + "' --width " + std::to_string(kWidth) +
                            " --height " + std::to_string(kHeight) + " --pixel-size 0.5" +
                            " --compare '" + ref.string() + "' 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return -1;
    std::string out;
    char buf[512];
    while (std::fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = pclose(pipe);
    double a = -1;
    if (status != 0 || std::sscanf(out.c_str(), "agreement %lf", &a) != 1) {
      ADD_FAILURE() << name << ": scad_raster.py failed: " << out;
      return -1;
    }
    std::printf("  %-14s %s", name.c_str(), out.c_str());
    return a;
  }

  fs::path dir_;
};

TEST_F(ScadRoundTrip, SampleTree) {
  EXPECT_GE(agreement(testing::sample_tree(), "sample", 0), 0.995);
}

TEST_F(ScadRoundTrip, SampleTreeExtruded) {
  EXPECT_GE(agreement(testing::sample_tree(), "sample_3d", 2.5), 0.995);
}

TEST_F(ScadRoundTrip, SharedDimensionsRenderAsTheTree) {
  // Equal holes and a concentric pair: the shared parameters draw what the tree holds.
  auto c = [](double x, double y, double r) { return Node::leaf(Primitive::circle(x, y, r)); };
  const Node plate = Node::op(
      NodeKind::Difference,
      {Node::op(NodeKind::Union, {Node::leaf(Primitive::rectangle(40, 30, 60, 30)), c(75, 30, 15)}),
       c(20.5, 30.5, 5.5), c(45.5, 30.5, 5.5), c(75, 30, 6.25)});
  EXPECT_GE(agreement(plate, "shared", 0), 0.995);
}

TEST_F(ScadRoundTrip, RandomTrees) {
  std::mt19937_64 rng(2024);
  for (int i = 0; i < 8; ++i) {
    Node tree;
    // Trees that cover almost nothing would agree trivially.
    do tree = testing::random_tree(rng, kWidth, kHeight, 3);
    while (render(tree, kWidth, kHeight).count() < 300);
    EXPECT_GE(agreement(tree, "random_" + std::to_string(i), i == 5 ? 4.0 : 0.0), 0.995)
        << structure_string(tree);
  }
}

}  // namespace
}  // namespace csgfit
