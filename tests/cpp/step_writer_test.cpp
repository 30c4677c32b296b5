// The STEP writer: every primitive's OpenCASCADE solid has the primitive's volume and lies where
// primitive3d.h / primitive.h put it; trees have the volume of their voxel rendering within what
// the grid can resolve; the file reads back as one valid solid in mm; bad input is refused
// without touching the output path.
#include "step_writer.h"

#include <gtest/gtest.h>

#include <BRepCheck_Analyzer.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Reader.hxx>
#include <TopAbs_State.hxx>
#include <TopExp_Explorer.hxx>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>

#include "csgfit/error.h"
#include "csgfit/model/frame.h"
#include "step_shape.h"

namespace csgfit {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

// A tilt that is no multiple of 90 degrees about any axis.
const Quaternion kTilt = Quaternion::from_euler_deg(23, -37, 61);

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("csgfit-step-test-" + std::to_string(getpid()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Points in (a little beyond) the solid's bounds, classified by OCCT and by the primitive's own
// contains(); points within `margin` of the surface are skipped (both answers are right there).
template <class Inside, class Distance>
void expect_same_points(const TopoDS_Shape& shape, const Bounds3& b, const Inside& inside,
                        const Distance& distance, const std::string& what) {
  std::mt19937 rng(7);
  int agreed = 0, checked = 0;
  const double span = std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  for (int i = 0; i < 200; ++i) {
    double p[3];
    for (int a = 0; a < 3; ++a) {
      const double pad = 0.1 * (b.hi[a] - b.lo[a]) + 1e-3;
      p[a] = std::uniform_real_distribution<double>(b.lo[a] - pad, b.hi[a] + pad)(rng);
    }
    if (std::fabs(distance(p[0], p[1], p[2])) < 1e-3 * span) continue;
    BRepClass3d_SolidClassifier cls(shape, gp_Pnt(p[0], p[1], p[2]), 1e-7);
    const bool occ_in = cls.State() == TopAbs_IN;
    ++checked;
    if (occ_in == inside(p[0], p[1], p[2])) ++agreed;
  }
  EXPECT_GT(checked, 150) << what;
  EXPECT_EQ(agreed, checked) << what << ": OCCT's solid is not where the primitive is";
}

Primitive3D polygonal(Primitive3D p, int sides) {
  p.sides = sides;
  return p;
}

std::vector<Primitive3D> tilted_primitives() {
  return {
      Primitive3D::box(1, 2, 3, 4, 2.5, 1.5, kTilt),
      Primitive3D::sphere(-1, 0.5, 2, 1.7),
      Primitive3D::cylinder(0, 0, 0, 1.2, 3.5, kTilt),
      Primitive3D::cone(2, -1, 0.5, 1.5, 0.6, 2.8, kTilt),        // frustum
      Primitive3D::cone(0, 1, -2, 0, 1.3, 2.2, kTilt),            // tip at the bottom (r1 = 0)
      Primitive3D::cone(0, 1, -2, 1.1, 0, 2.2, kTilt),            // tip at the top (r2 = 0)
      Primitive3D::ellipsoid(1, 1, 1, 2.5, 1.2, 0.8, kTilt),
      Primitive3D::torus(-2, 0, 1, 2.0, 0.7, kTilt),
      Primitive3D::torus(0, 0, 0, 1.0, 1.0, kTilt),               // horn torus (r = R)
      Primitive3D::prism(0.5, -0.5, 1, 3, 2, 1.5, 0.6, kTilt),    // off-centre apex
      Primitive3D::prism(0, 0, 0, 2, 3, 1, -1, kTilt),            // right-angled
      polygonal(Primitive3D::cylinder(1, 0, 0, 1.2, 3.5, kTilt), 6),        // nut trap
      polygonal(Primitive3D::cone(2, -1, 0.5, 1.5, 0.6, 2.8, kTilt), 8),    // pyramid frustum
      polygonal(Primitive3D::cone(0, 1, -2, 0, 1.3, 2.2, kTilt), 5),        // tip at the bottom
      polygonal(Primitive3D::cone(0, 1, -2, 1.1, 0, 2.2, kTilt), 3),        // tip at the top
      polygonal(Primitive3D::cone(0, 1, -2, 1.1, 1.1, 2.2, kTilt), 12),     // radii equal
      Primitive3D::rounded_box(1, 2, 3, 4, 2.5, 1.5, 0.6, kTilt),
      Primitive3D::rounded_box(-1, 0, 1, 4, 2.5, 1.5, 1.25, kTilt),        // stadium
      Primitive3D::rounded_box(0, 1, 0, 2, 2, 3, 1, kTilt),                // disc
  };
}

TEST(StepWriter, EachTiltedPrimitiveHasItsVolumeAndPlace) {
  for (const Primitive3D& p : tilted_primitives()) {
    const std::string what = std::string(to_string(p.kind)) + " dims " + std::to_string(p.dims[0]) +
                             "," + std::to_string(p.dims[1]) + "," + std::to_string(p.dims[2]);
    const TopoDS_Shape shape = make_shape(Node3D::leaf(p));
    ASSERT_TRUE(BRepCheck_Analyzer(shape).IsValid()) << what;
    const double v = shape_volume(shape);
    EXPECT_NEAR(v, p.volume(), 0.005 * p.volume()) << what;
    expect_same_points(
        shape, p.bounds(), [&](double x, double y, double z) { return p.contains(x, y, z); },
        [&](double x, double y, double z) { return p.signed_distance(x, y, z); }, what);
  }
}

// Polygonal cylinders and cones have plane faces only: their solids' volumes are exact.
TEST(StepWriter, PolygonalPrimitivesHaveTheirExactVolume) {
  for (const Primitive3D& p : tilted_primitives()) {
    if (!p.is_polygonal()) continue;
    EXPECT_NEAR(shape_volume(make_shape(p)), p.volume(), 1e-9 * p.volume()) << p.sides << " sides";
  }
}

// A rounded box's faces are planes and quarter cylinders: its solid's volume is exact.
TEST(StepWriter, RoundedBoxesHaveTheirExactVolume) {
  int n = 0;
  for (const Primitive3D& p : tilted_primitives()) {
    if (p.kind != PrimitiveKind3D::RoundedBox) continue;
    ++n;
    EXPECT_NEAR(shape_volume(make_shape(p)), p.volume(), 1e-9 * p.volume()) << "corner " << p.corner;
  }
  EXPECT_EQ(n, 3);
  Primitive3D over = Primitive3D::rounded_box(0, 0, 0, 4, 2, 1, 1);
  over.corner = 1.1;
  EXPECT_THROW(make_shape(over), InputError);
}

TEST(StepWriter, EachExtruded2DPrimitiveHasItsVolumeAndPlace) {
  ModelFrame frame;
  frame.pixel_size = 0.25;
  frame.thickness = 2.0;
  const std::vector<Primitive> prims = {
      Primitive::rectangle(40, 30, 20, 8, 33), Primitive::circle(10, 12, 6),
      Primitive::ellipse(20, 20, 12, 5, 117),  Primitive::ellipse(20, 20, 4, 9, 20),
      Primitive::triangle(30, 10, 16, 10, 250, 0.7)};
  for (const Primitive& p : prims) {
    const std::string what = std::string(to_string(p.kind));
    const TopoDS_Shape shape = make_shape(Node::leaf(p), frame);
    ASSERT_TRUE(BRepCheck_Analyzer(shape).IsValid()) << what;
    const double s = frame.pixel_size;
    EXPECT_NEAR(shape_volume(shape), p.area() * s * s * frame.thickness,
                1e-6 * p.area() * s * s * frame.thickness)
        << what;
    // Model = pixel * pixel_size, y up, z in [0, thickness]: the 2D .scad writer's frame.
    const double r = std::max(p.w, p.h) * s;
    Bounds3 b;
    b.lo = {p.cx * s - r, p.cy * s - r, 0};
    b.hi = {p.cx * s + r, p.cy * s + r, frame.thickness};
    expect_same_points(
        shape, b,
        [&](double x, double y, double z) {
          return z >= 0 && z <= frame.thickness && p.contains(x / s, y / s);
        },
        [&](double x, double y, double z) {
          return std::max({p.signed_distance(x / s, y / s) * s, -z, z - frame.thickness});
        },
        what);
  }
}

// A part with every operator and tilted round primitives.
Node3D sample_tree() {
  const Node3D plate = Node3D::op(
      NodeKind::Difference,
      {Node3D::leaf(Primitive3D::box(0, 0, 0, 12, 9, 4, Quaternion::from_euler_deg(0, 0, 10))),
       Node3D::leaf(Primitive3D::cylinder(2, 1, 0, 1.5, 6, Quaternion::from_euler_deg(20, 10, 0))),
       Node3D::leaf(Primitive3D::prism(-3, -2, 1.5, 3, 2.5, 4, 0.3, kTilt))});
  const Node3D knob = Node3D::op(
      NodeKind::Intersection,
      {Node3D::leaf(Primitive3D::sphere(-3, 2, 2.5, 2.6)),
       Node3D::leaf(Primitive3D::cone(-3, 2, 2.5, 2.4, 0.8, 4, Quaternion::from_euler_deg(10, 0, 0)))});
  return Node3D::op(NodeKind::Union,
                    {plate, knob,
                     Node3D::leaf(Primitive3D::ellipsoid(4, -2, 2, 2.5, 1.5, 1.2, kTilt)),
                     Node3D::leaf(Primitive3D::torus(5, 3, 1.5, 1.6, 0.5, kTilt))});
}

TEST(StepWriter, TreeVolumeMatchesItsVoxelRendering) {
  const Node3D tree = sample_tree();
  const double v_occ = step_volume(tree);

  // Voxel estimate on a grid of h: each voxel counts fully or not at all by its centre, so the
  // estimate differs from the exact volume only in voxels the surface passes through, by less
  // than one voxel each. Those voxels have a centre within sqrt(3)/2 h of the surface, and the
  // tree's signed distance is a lower bound of the true one, so counting |sd| <= sqrt(3)/2 h
  // bounds the error from above: a hard bound, but a loose one (17 % here).
  //
  // The real error is much smaller: across a surface that is not aligned with the grid the
  // centre samples err both ways and cancel to first order in h, leaving a curvature term and
  // noise; the one axis-aligned pair of faces (the plate's z = +-2) falls on voxel boundaries,
  // the grid being anchored there (4 mm = 50 h), so its centres are h/2 either side, with no
  // bias. Measured: 0.013 % at h = 0.08 mm (0.10 % with the
  // faces at voxel centres). The tolerance, 0.5 %, is checked to be under what
  // dropping the smallest primitive (the torus, partly inside the plate) changes.
  Bounds3 b;
  b.lo = {1e300, 1e300, 1e300};
  b.hi = {-1e300, -1e300, -1e300};
  for (const Primitive3D* p : leaves(tree)) {
    const Bounds3 pb = p->bounds();
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], pb.lo[a]);
      b.hi[a] = std::max(b.hi[a], pb.hi[a]);
    }
  }
  const double h = 0.08;
  const int n[3] = {static_cast<int>(std::ceil((b.hi[0] - b.lo[0]) / h)) + 2,
                    static_cast<int>(std::ceil((b.hi[1] - b.lo[1]) / h)) + 2,
                    static_cast<int>(std::ceil((b.hi[2] - b.lo[2]) / h)) + 2};
  const double oz = -2 - h * std::ceil((-2 - b.lo[2]) / h + 1);  // z = -2 on a voxel boundary
  const VoxelGrid frame(n[0], n[1], n[2] + 1, b.lo[0] - h, b.lo[1] - h, oz, h);
  const VoxelGrid grid = render(tree, frame);
  const double cell = h * h * h;
  const double v_vox = static_cast<double>(grid.count()) * cell;
  std::size_t shell = 0;
  const double reach = std::sqrt(3.0) / 2 * h;
  for (int k = 0; k < frame.nz(); ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        if (std::fabs(signed_distance(tree, frame.center_x(i), frame.center_y(j), frame.center_z(k))) <= reach)
          ++shell;
  const double bound = static_cast<double>(shell) * cell;
  // The bound must be small enough for the comparison to mean something.
  std::printf("OCCT %.4f, voxel %.4f (diff %.3f %%), shell bound %.4f (%.1f %%)\n", v_occ, v_vox,
              100 * (v_vox - v_occ) / v_occ, bound, 100 * bound / v_occ);
  EXPECT_NEAR(v_occ, v_vox, bound);
  const double tolerance = 0.005 * v_occ;
  EXPECT_NEAR(v_occ, v_vox, tolerance);
  Node3D without_torus = tree;
  ASSERT_EQ(without_torus.children.back().primitive.kind, PrimitiveKind3D::Torus);
  without_torus.children.pop_back();
  const double v_without = step_volume(without_torus);
  std::printf("without the torus: %.4f (%.2f %%)\n", v_without, 100 * (v_without - v_occ) / v_occ);
  EXPECT_GT(std::fabs(v_without - v_vox), 2 * tolerance)
      << "the test could not see a primitive go missing";
}

TEST(StepWriter, FileReadsBackAsOneValidSolidInMillimetres) {
  TempDir dir;
  const fs::path out = dir.path / "part.step";
  const Node3D tree = sample_tree();
  StepOptions options;
  options.source = "part.stl";
  write_step(tree, out.string(), options);
  ASSERT_TRUE(fs::exists(out));
  // No temporary file is left behind.
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.path)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);

  STEPControl_Reader reader;
  ASSERT_EQ(reader.ReadFile(out.c_str()), IFSelect_RetDone);
  ASSERT_GT(reader.TransferRoots(), 0);
  const TopoDS_Shape back = reader.OneShape();
  int solids = 0;
  for (TopExp_Explorer ex(back, TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
  EXPECT_EQ(solids, 1);
  EXPECT_TRUE(BRepCheck_Analyzer(back).IsValid());
  // Same volume in the reader's units (mm): a file in metres or inches would be off by 1e9
  // or 16387.
  const double v = step_volume(tree);
  EXPECT_NEAR(shape_volume(back), v, 1e-6 * v);
}

TEST(StepWriter, Extruded2DTreeReadsBack) {
  TempDir dir;
  const fs::path out = dir.path / "plate.stp";
  ModelFrame frame;
  frame.pixel_size = 0.5;
  frame.thickness = 3;
  const Node tree = Node::op(NodeKind::Difference,
                             {Node::leaf(Primitive::rectangle(50, 40, 80, 60, 15)),
                              Node::leaf(Primitive::circle(50, 40, 10)),
                              Node::leaf(Primitive::triangle(25, 30, 12, 10, 40, 0.5))});
  write_step(tree, frame, out.string());
  STEPControl_Reader reader;
  ASSERT_EQ(reader.ReadFile(out.c_str()), IFSelect_RetDone);
  reader.TransferRoots();
  const TopoDS_Shape back = reader.OneShape();
  EXPECT_TRUE(BRepCheck_Analyzer(back).IsValid());
  const double s = frame.pixel_size;
  const double expected = (80.0 * 60 - kPi * 10 * 10 - 12.0 * 10 / 2) * s * s * frame.thickness;
  EXPECT_NEAR(shape_volume(back), expected, 1e-6 * expected);
}

TEST(StepWriter, BadInputIsOneLineAndLeavesTheFileAlone) {
  TempDir dir;
  const fs::path out = dir.path / "keep.step";
  { std::ofstream(out) << "old contents"; }
  auto expect_refused = [&](const auto& write, const std::string& words) {
    try {
      write();
      ADD_FAILURE() << "no error; expected one about " << words;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(words), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    EXPECT_EQ(read_file(out), "old contents");
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir.path)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u) << "a temporary file was left behind";
  };

  ModelFrame flat;  // thickness 0
  const Node disc = Node::leaf(Primitive::circle(10, 10, 5));
  expect_refused([&] { write_step(disc, flat, out.string()); }, "STEP needs a thickness");

  // Two boxes that do not meet: their intersection is empty.
  const Node3D nothing = Node3D::op(NodeKind::Intersection,
                                    {Node3D::leaf(Primitive3D::box(0, 0, 0, 1, 1, 1)),
                                     Node3D::leaf(Primitive3D::box(5, 0, 0, 1, 1, 1))});
  expect_refused([&] { write_step(nothing, out.string()); }, "empty");

  Primitive3D bad = Primitive3D::box(0, 0, 0, 1, 1, 1);
  bad.dims[1] = -2;
  expect_refused([&] { write_step(Node3D::leaf(bad), out.string()); }, "size y");
  bad = Primitive3D::sphere(std::nan(""), 0, 0, 1);
  expect_refused([&] { write_step(Node3D::leaf(bad), out.string()); }, "centre x");

  const Node3D ok = Node3D::leaf(Primitive3D::box(0, 0, 0, 1, 1, 1));
  EXPECT_THROW(write_step(ok, (dir.path / "no-such-folder" / "x.step").string()), InputError);
  EXPECT_THROW(write_step(ok, dir.path.string()), InputError);  // a folder
}

TEST(StepWriter, DisjointPiecesStaySeparateSolidsButSliversGo) {
  // Two boxes apart: two solids, nothing lost.
  const Node3D two = Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(0, 0, 0, 2, 2, 2)),
                                                  Node3D::leaf(Primitive3D::box(5, 0, 0, 1, 1, 1))});
  const TopoDS_Shape shape = make_shape(two);
  int solids = 0;
  for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
  EXPECT_EQ(solids, 2);
  EXPECT_NEAR(shape_volume(shape), 9.0, 1e-9);
  // A 1e-3 cube beside a 1000 mm^3 one (1e-12 of it): a sliver, dropped.
  const Node3D sliver = Node3D::op(NodeKind::Union, {Node3D::leaf(Primitive3D::box(0, 0, 0, 10, 10, 10)),
                                                     Node3D::leaf(Primitive3D::box(8, 0, 0, 1e-3, 1e-3, 1e-3))});
  const TopoDS_Shape one = make_shape(sliver);
  solids = 0;
  for (TopExp_Explorer ex(one, TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
  EXPECT_EQ(solids, 1);
  EXPECT_NEAR(shape_volume(one), 1000.0, 1e-6);
}

TEST(StepWriter, StepPathsAreRecognised) {
  EXPECT_TRUE(is_step_path("a/b.step"));
  EXPECT_TRUE(is_step_path("B.STP"));
  EXPECT_FALSE(is_step_path("b.scad"));
  EXPECT_FALSE(is_step_path("step"));
}

}  // namespace
}  // namespace csgfit
