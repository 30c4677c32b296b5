// The range readers and normals: the benchmark's depth images back-projected onto the cube they
// show, the .npy forms, point files, and every bad input refused with one line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/features/point_normals.h"
#include "csgfit/io/range_read.h"
#include "hand_png.h"
#include "scratch_dir.h"

namespace csgfit {
namespace {

namespace fs = std::filesystem;

const fs::path kRange = fs::path(CSGFIT_SOURCE_DIR) / ".." / "shared" / "benchmarks" / "range";

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A grey PNG of `bits` 8 or 16 from row-major values, encoded by hand.
std::string encode_png(int w, int h, int bits, const std::vector<std::uint16_t>& values) {
  std::vector<std::string> rows(static_cast<std::size_t>(h));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::uint16_t x = values[static_cast<std::size_t>(v * w + u)];
      if (bits == 16) rows[v] += static_cast<char>(x >> 8);
      rows[v] += static_cast<char>(x & 0xff);
    }
  }
  return testing::make_png(w, h, bits, 0, rows);
}

std::string npy(const std::string& descr, const std::string& shape, const std::string& data) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  return std::string("\x93NUMPY\x01\x00", 8) + char(dict.size() & 0xff) + char(dict.size() >> 8) +
         dict + data;
}

std::string floats(const std::vector<float>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}

const char* kOrthoSidecar = R"({"projection": "orthographic", "pixel_size": 0.5, "cx": 2, "cy": 2,
  "width": 4, "height": 4, "camera_to_world": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
  "depth_unit": 0.01, "no_return": 0})";

class RangeReadTest : public testing::ScratchDirTest {
 protected:
  // A benchmark file copied into the scratch folder (so that it can lose its sidecar).
  std::string copy(const std::string& name, const std::string& as) {
    return file(as, read_bytes(kRange / name));
  }
  static bool have_benchmarks() { return fs::is_directory(kRange); }

  // The InputError of reading `path`, checked to be one line naming `names`.
  std::string error_of(const std::function<void()>& f, const std::string& names) {
    try {
      f();
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_NE(m.find(names), std::string::npos) << "does not name " << names << ": " << m;
      return m;
    }
    ADD_FAILURE() << "no InputError";
    return "";
  }
  std::string read_error(const std::string& path, const RangeReadOptions& o = {}) {
    return error_of([&] { read_range(path, o); }, path);
  }
  // A 4 x 4 16-bit depth image with the orthographic sidecar above: depth 1 everywhere.
  std::string small_png(const std::string& stem, const std::string& sidecar = kOrthoSidecar) {
    if (!sidecar.empty()) file(stem + ".json", sidecar);
    return file(stem + ".png", encode_png(4, 4, 16, std::vector<std::uint16_t>(16, 100)));
  }
};

// The benchmark's one_cube: cube(10, center = true).
double cube_distance(const Vec3& p) {
  return std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}) - 5;
}

// Every point on the cube's surface; points away from its edges have the face's normal.
void expect_on_cube(const RangeScan& s, double tolerance) {
  ASSERT_GT(s.points.size(), 5000u);
  ASSERT_EQ(s.normals.size(), s.points.size());
  std::size_t off = 0, checked = 0, wrong = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const Vec3& p = s.points[i];
    if (std::abs(cube_distance(p)) > tolerance) ++off;
    int axis = 0;
    for (int a = 1; a < 3; ++a) axis = std::abs(p[a]) > std::abs(p[axis]) ? a : axis;
    bool inner = true;
    for (int a = 0; a < 3; ++a) inner = inner && (a == axis || std::abs(p[a]) < 4.5);
    if (!inner) continue;
    ++checked;
    const double along = s.normals[i][axis] * (p[axis] > 0 ? 1 : -1);
    if (along < 0.995) ++wrong;
  }
  EXPECT_EQ(off, 0u);
  EXPECT_GT(checked, s.points.size() / 2);
  EXPECT_EQ(wrong, 0u);
}

TEST_F(RangeReadTest, OrthographicBenchmarkImageLandsOnTheCube) {
  if (!have_benchmarks()) GTEST_SKIP() << "no benchmarks at " << kRange;
  const RangeScan s = read_range((kRange / "one_cube_ortho.png").string());
  ASSERT_TRUE(s.camera && s.camera->projection == Projection::Orthographic);
  EXPECT_EQ(s.width, 192);
  EXPECT_EQ(s.pixel.size(), s.points.size());
  EXPECT_TRUE(std::is_sorted(s.pixel.begin(), s.pixel.end()));
  EXPECT_EQ(s.points.size() + s.dropped_no_return + s.dropped_outliers, 192u * 192u);
  EXPECT_GT(s.dropped_no_return, 0u);
  expect_on_cube(s, 0.01);
  // The pixel's own ray goes through its point.
  const std::size_t i = s.points.size() / 2;
  const int u = s.pixel[i] % 192, v = s.pixel[i] / 192;
  const Vec3 uvd = s.camera->project(s.points[i]);
  EXPECT_NEAR(uvd[0], u, 1e-6);
  EXPECT_NEAR(uvd[1], v, 1e-6);
}

TEST_F(RangeReadTest, PinholeBenchmarkImageLandsOnTheCube) {
  if (!have_benchmarks()) GTEST_SKIP() << "no benchmarks at " << kRange;
  const RangeScan s = read_range((kRange / "one_cube_pinhole.png").string());
  ASSERT_TRUE(s.camera && s.camera->projection == Projection::Pinhole);
  // The pinhole image carries noise of 0.1 % of the diagonal (0.017): 4 sigma.
  expect_on_cube(s, 0.07);
  const RangeCamera& c = *s.camera;
  const Vec3 o = c.ray_origin(10, 20), d = c.ray_direction(10, 20), p = c.world_point(10, 20, 30);
  const double t = std::sqrt((p[0] - o[0]) * (p[0] - o[0]) + (p[1] - o[1]) * (p[1] - o[1]) +
                             (p[2] - o[2]) * (p[2] - o[2]));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(o[k] + t * d[k], p[k], 1e-6);
  const Vec3 back = c.project(p);
  EXPECT_NEAR(back[0], 10, 1e-9);
  EXPECT_NEAR(back[1], 20, 1e-9);
  EXPECT_NEAR(back[2], 30, 1e-9);
}

TEST_F(RangeReadTest, NpyDepthAgreesWithThePng) {
  if (!have_benchmarks()) GTEST_SKIP() << "no benchmarks at " << kRange;
  const RangeScan png = read_range((kRange / "one_cube_ortho.png").string());
  const RangeScan arr = read_range((kRange / "one_cube_ortho.npy").string());
  ASSERT_EQ(arr.pixel, png.pixel);
  const double unit = png.camera->depth_unit;
  for (std::size_t i = 0; i < png.points.size(); ++i) {
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(arr.points[i][k], png.points[i][k], unit);
  }
}

TEST_F(RangeReadTest, OrganisedXyzCloudTurnsItsNormalsOutwards) {
  if (!have_benchmarks()) GTEST_SKIP() << "no benchmarks at " << kRange;
  const RangeScan s = read_range((kRange / "one_cube_xyz.npy").string());
  EXPECT_FALSE(s.camera);
  EXPECT_EQ(s.width, 192);
  expect_on_cube(s, 1e-3);
  // Without the ortho sidecar next to it: away from the centroid, still outwards.
  expect_on_cube(read_range(copy("one_cube_xyz.npy", "alone_xyz.npy")), 1e-3);
}

std::vector<Vec3> sphere_points(int n) {
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z), a = 2.39996323 * i;
    p.push_back({r * std::cos(a), r * std::sin(a), z});
  }
  return p;
}

void expect_radial(const RangeScan& s, std::size_t count) {
  ASSERT_EQ(s.points.size(), count);
  ASSERT_EQ(s.normals.size(), count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3& p = s.points[i];
    const double dot = p[0] * s.normals[i][0] + p[1] * s.normals[i][1] + p[2] * s.normals[i][2];
    EXPECT_GT(dot, 0.97) << i;
  }
}

TEST_F(RangeReadTest, XyzTextGetsOutwardNormalsAndDropsNaNAndOutliers) {
  std::string text = "# a unit sphere\n";
  for (const Vec3& p : sphere_points(600)) {
    text += std::to_string(p[0]) + " " + std::to_string(p[1]) + "\t" + std::to_string(p[2]) + "\n";
  }
  text += "nan nan nan\n30 30 30  # far away\n";
  const RangeScan s = read_range(file("sphere.xyz", text));
  EXPECT_FALSE(s.organised());
  EXPECT_TRUE(s.pixel.empty());
  EXPECT_EQ(s.dropped_no_return, 1u);
  EXPECT_EQ(s.dropped_outliers, 1u);
  expect_radial(s, 600);
  // Normals in the file are kept (normalised); a zero one is an outlier.
  const RangeScan n = read_range(file("n.xyz", "0 0 1 0 0 2\n1 0 0 0 0 0\n0 1 0 0 3 0\n"));
  ASSERT_EQ(n.points.size(), 2u);
  EXPECT_EQ(n.dropped_outliers, 1u);
  EXPECT_EQ(n.normals[0], (Vec3{0, 0, 1}));
  EXPECT_EQ(n.normals[1], (Vec3{0, 1, 0}));
}

std::string ply_header(const std::string& format, std::size_t n, bool normals,
                       const std::string& extra = "") {
  std::string h = "ply\nformat " + format + " 1.0\ncomment made by hand\n" + extra +
                  "element vertex " + std::to_string(n) +
                  "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
  return h + "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string binary_ply(const std::vector<Vec3>& pts, bool big) {
  std::string body;
  for (const Vec3& p : pts) {
    for (double c : p) {
      const float f = static_cast<float>(c);
      char b[4];
      std::memcpy(b, &f, 4);
      if (big) std::reverse(b, b + 4);
      body.append(b, 4);
    }
  }
  return ply_header(big ? "binary_big_endian" : "binary_little_endian", pts.size(), false) + body;
}

TEST_F(RangeReadTest, PlyAsciiAndBinaryPointClouds) {
  const std::vector<Vec3> pts = sphere_points(500);
  std::string ascii = ply_header("ascii", pts.size(), true);
  for (const Vec3& p : pts) {
    for (int k = 0; k < 6; ++k) ascii += std::to_string(p[k % 3]) + (k == 5 ? "\n" : " ");
  }
  const RangeScan a = read_range(file("a.ply", ascii));
  expect_radial(a, 500);
  EXPECT_NEAR(a.normals[7][0], pts[7][0], 1e-5);  // the file's own normals
  expect_radial(read_range(file("le.ply", binary_ply(pts, false))), 500);
  const RangeScan be = read_range(file("be.ply", binary_ply(pts, true)));
  expect_radial(be, 500);
  EXPECT_NEAR(be.points[3][2], pts[3][2], 1e-6);
}

TEST_F(RangeReadTest, PlyWithWidthAndHeightIsOrganised) {
  // A 20 x 15 grid over a dome z = sqrt(4 - x^2 - y^2), one pixel without a return.
  std::vector<Vec3> pts;
  for (int v = 0; v < 15; ++v) {
    for (int u = 0; u < 20; ++u) {
      const double x = (u - 9.5) * 0.08, y = (v - 7) * 0.08;
      pts.push_back({x, y, std::sqrt(4 - x * x - y * y)});
    }
  }
  pts[37] = {NAN, NAN, NAN};
  std::string text = ply_header("ascii", 300, false, "obj_info width 20\nobj_info height 15\n");
  for (const Vec3& p : pts) {
    text += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  }
  const RangeScan s = read_range(file("dome.ply", text));
  ASSERT_TRUE(s.organised());
  EXPECT_EQ(s.width, 20);
  EXPECT_EQ(s.dropped_no_return, 1u);
  ASSERT_EQ(s.points.size(), 299u);
  EXPECT_EQ(s.pixel[37], 38);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const Vec3& p = s.points[i];
    const double dot =
        (p[0] * s.normals[i][0] + p[1] * s.normals[i][1] + p[2] * s.normals[i][2]) / 2;
    EXPECT_GT(dot, 0.995) << i;  // the corners' one-sided windows lean by up to 3 degrees
  }
}

TEST_F(RangeReadTest, IntrinsicsReplaceAMissingSidecar) {
  const std::string png = small_png("bare", "");
  RangeReadOptions o;
  o.intrinsics.pixel_size = 0.5;
  o.intrinsics.depth_unit = 0.01;
  const RangeScan s = read_range(png, o);
  EXPECT_EQ(s.points.size(), 16u);
  EXPECT_NEAR(s.points[0][0], (0.5 - 2) * 0.5, 1e-12);  // cx defaults to the centre
  EXPECT_NEAR(s.points[0][2], 1.0, 1e-12);
  EXPECT_NEAR(s.normals[0][2], -1.0, 1e-9);  // towards the camera at z < 0
  o.intrinsics.fx = 100;
  EXPECT_NE(read_error(png, o).find("not both"), std::string::npos);
  // Over a sidecar, an option replaces its field.
  RangeReadOptions over;
  over.intrinsics.depth_unit = 0.02;
  EXPECT_NEAR(read_range(small_png("side"), over).points[0][2], 2.0, 1e-12);
}

TEST_F(RangeReadTest, PngWithoutSidecarOrIntrinsicsSaysWhatIsMissing) {
  const std::string png = small_png("lonely", "");
  const std::string m = read_error(png);
  EXPECT_NE(m.find(dir_ + "/lonely.json"), std::string::npos) << m;
  EXPECT_NE(m.find("--pixel-size"), std::string::npos) << m;
  EXPECT_NE(m.find("--fx"), std::string::npos) << m;
  EXPECT_FALSE(read_range_camera(png, 4, 4, {}));
}

std::string with(const std::string& from, const std::string& to) {
  std::string s = kOrthoSidecar;
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST_F(RangeReadTest, BadSidecarsAreRefused) {
  const struct {
    std::string sidecar, says;
  } cases[] = {
      {with("[1,0,0,0],[0,1,0,0],[0,0,1,0]", "[0,0,0,0],[0,0,0,0],[0,0,0,0]"), "orthonormal"},
      {with("[1,0,0,0],[0,1,0,0]", "[2,0,0,0],[0,2,0,0]"), "orthonormal"},
      {with("[1,0,0,0]", "[-1,0,0,0]"), "determinant"},
      {with("[0,0,0,1]]", "[0,0,1,1]]"), "last row"},
      {with("[[1,0,0,0],", "[[1,0,0],"), "4 rows of 4"},
      {with("\"pixel_size\": 0.5", "\"pixel_size\": -0.5"), "pixel_size must be positive"},
      {with("\"orthographic\", \"pixel_size\": 0.5", "\"pinhole\", \"fx\": 0, \"fy\": 1"),
       "fx must be positive"},
      {with("\"pixel_size\": 0.5", "\"pixel_size\": NaN"), "NaN"},
      {with("\"depth_unit\": 0.01", "\"depth_unit\": 1e999"), "overflow"},
      {with("\"width\": 4", "\"width\": 5"), "5 x 4"},
      {with("\"orthographic\"", "\"fisheye\""), "projection"},
      {"[1, 2]", "not a JSON object"},
      {"{\"pixel_size\": ", "not valid JSON"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const std::string stem = "bad" + std::to_string(n++);
    const std::string png = small_png(stem, c.sidecar);
    const std::string m = error_of([&] { read_range(png); }, dir_ + "/" + stem + ".json");
    EXPECT_NE(m.find(c.says), std::string::npos) << c.sidecar << "\n" << m;
  }
}

TEST_F(RangeReadTest, BadImagesAreRefused) {
  file("eight.json", kOrthoSidecar);
  const std::string eight = file("eight.png", encode_png(4, 4, 8, std::vector<std::uint16_t>(16, 9)));
  EXPECT_NE(read_error(eight).find("is an 8-bit image; a depth image must be 16-bit"),
            std::string::npos);
  file("empty.json", kOrthoSidecar);
  const std::string empty = file("empty.png", encode_png(4, 4, 16, std::vector<std::uint16_t>(16)));
  EXPECT_NE(read_error(empty).find("no returns"), std::string::npos);
  file("nan.json", kOrthoSidecar);
  const std::string nan = file("nan.npy", npy("<f4", "(4, 4)", floats(std::vector<float>(16, NAN))));
  EXPECT_NE(read_error(nan).find("no returns"), std::string::npos);

  const std::string whole = encode_png(4, 4, 16, std::vector<std::uint16_t>(16, 100));
  file("cut.json", kOrthoSidecar);
  const std::string cut = file("cut.png", whole.substr(0, whole.size() - 20));
  EXPECT_NE(read_error(cut).find("truncated"), std::string::npos);
  std::string huge = whole;
  huge.replace(16, 8, testing::be32(100000) + testing::be32(100000));
  EXPECT_NE(read_error(file("huge.png", huge)).find("over the limit"), std::string::npos);
  EXPECT_NE(read_error(file("text.png", "hello")).find("not a PNG"), std::string::npos);
  EXPECT_NE(read_error(file("x.tif", "II*")).find("unknown range format"), std::string::npos);
  EXPECT_NE(read_error(dir_ + "/missing.png").find("cannot open"), std::string::npos);
}

TEST_F(RangeReadTest, BadArraysAndCloudsAreRefused) {
  file("d.json", kOrthoSidecar);
  const std::string data = floats(std::vector<float>(16, 1.0f));
  EXPECT_EQ(read_range(file("d.npy", npy("<f4", "(4, 4)", data))).points.size(), 16u);
  EXPECT_NE(read_error(file("d.npy", npy("<f4", "(4, 4)", data.substr(0, 40)))).find("truncated"),
            std::string::npos);
  EXPECT_NE(read_error(file("big.npy", npy("<f4", "(100000, 100000)", data))).find("over the limit"),
            std::string::npos);
  EXPECT_NE(read_error(file("s.npy", npy("<f4", "(4, 4, 2)", data + data))).find("H x W x 3"),
            std::string::npos);
  EXPECT_NE(read_error(file("i.npy", npy("<i4", "(4, 4)", data))).find("float32"),
            std::string::npos);
  EXPECT_NE(read_error(file("nosc.npy", npy("<f4", "(4, 4)", data))).find("--pixel-size"),
            std::string::npos);

  const std::string ply = binary_ply(sphere_points(50), false);
  EXPECT_NE(read_error(file("cut.ply", ply.substr(0, ply.size() - 30))).find("truncated"),
            std::string::npos);
  std::string many = ply_header("binary_little_endian", 0, false);
  many.replace(many.find("vertex 0"), 8, "vertex 999999999999");
  EXPECT_NE(read_error(file("many.ply", many)).find("over the limit"), std::string::npos);
  EXPECT_NE(read_error(file("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"))
                .find("end_header"),
            std::string::npos);
  EXPECT_NE(read_error(file("bad.xyz", "1 2 3\n4 5 six\n")).find("line 2"), std::string::npos);
  EXPECT_NE(read_error(file("mixed.xyz", "1 2 3\n4 5 6 0 0 1\n")).find("line 2"),
            std::string::npos);
  EXPECT_NE(read_error(file("none.xyz", "# nothing\nnan 0 0\n")).find("no returns"),
            std::string::npos);
  RangeReadOptions small;
  small.max_points = 10;
  std::string eleven;
  for (int i = 0; i < 11; ++i) eleven += "1 2 3\n";
  EXPECT_NE(read_error(file("ten.xyz", eleven), small).find("over the limit of 10"),
            std::string::npos);
  EXPECT_THROW(read_ranges({}), InputError);
}

TEST(RangeCameraTest, ValidateNamesWhatIsWrong) {
  RangeCamera c;
  c.width = 4;
  c.height = 4;
  c.pixel_size = 1;
  EXPECT_NO_THROW(c.validate());
  c.height = 0;
  EXPECT_THROW(c.validate(), InputError);
  c.height = 4;
  c.depth_unit = 0;
  EXPECT_THROW(c.validate(), InputError);
  c.depth_unit = 1;
  // A rotation of 90 degrees about z with a translation is rigid.
  c.camera_to_world = {0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 1, 7, 0, 0, 0, 1};
  EXPECT_NO_THROW(c.validate());
  const Vec3 p = c.world_point(1, 2, 3), uvd = c.project(p);
  EXPECT_NEAR(uvd[0], 1, 1e-12);
  EXPECT_NEAR(uvd[1], 2, 1e-12);
  EXPECT_NEAR(uvd[2], 3, 1e-12);
  c.camera_to_world[3] = NAN;
  EXPECT_THROW(c.validate(), InputError);
}

}  // namespace
}  // namespace csgfit
