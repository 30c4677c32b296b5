// OpenSCAD renders the .scad writer's polygonal cylinders and cones as the solver has them: the
// rendered solid (its STL read back, its volume by the divergence theorem, its inside by the
// winding number) has Primitive3D::volume() and agrees with contains() at points, among them
// points just inside a vertex and just outside an edge's middle, which a circle, an area-keeping
// radius or a lost turn about the axis would get wrong; and so does a rounded box, whose
// corners OpenSCAD's offset() draws as polygons. Skipped when openscad is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "csgfit/io/mesh_read.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/voxelize.h"
#include "scad_writer3d.h"
#include "scratch_dir.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

class ScadPolygonRender : public testing::ScratchDirTest {
 protected:
  void SetUp() override {
    if (std::system("command -v openscad >/dev/null 2>&1") != 0)
      GTEST_SKIP() << "openscad is not installed";
    ScratchDirTest::SetUp();
  }

  // OpenSCAD's rendering of the primitive as the writer writes it.
  TriangleMesh rendered(const Primitive3D& p, const std::string& name) {
    const std::string scad = file(name + ".scad", to_scad(Node3D::leaf(p)));
    const std::string stl = dir_ + "/" + name + ".stl";
    const std::string command =
        "openscad -o '" + stl + "' '" + scad + "' >'" + dir_ + "/" + name + ".log' 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << name << ": OpenSCAD failed";
    return read_mesh(stl);
  }

  // The rendering has p's volume within `relative` and agrees with contains() at `probes`.
  void expect_rendered_as_solved(const Primitive3D& p, const std::string& name, double relative,
                                 const std::vector<Vec3>& probes) {
    const TriangleMesh mesh = rendered(p, name);
    EXPECT_NEAR(std::fabs(signed_volume(mesh)), p.volume(), relative * p.volume()) << name;
    int disagree = 0;
    for (const Vec3& q : probes)
      disagree += (winding_number(mesh, q) > 0.5) != p.contains(q[0], q[1], q[2]);
    EXPECT_EQ(disagree, 0) << name;
  }
};

Vec3 model_point(const Primitive3D& p, const Vec3& l) {
  const Mat3 m = p.rotation.matrix();
  return {p.cx + m[0][0] * l[0] + m[0][1] * l[1] + m[0][2] * l[2],
          p.cy + m[1][0] * l[0] + m[1][1] * l[1] + m[1][2] * l[2],
          p.cz + m[2][0] * l[0] + m[2][1] * l[1] + m[2][2] * l[2]};
}

// `count` random points in p's bounds (one unit beyond them) that are not within 1 % of its size
// of its surface, appended to `out`.
void add_random_probes(const Primitive3D& p, std::size_t count, unsigned seed, std::vector<Vec3>& out) {
  const Bounds3 b = p.bounds();
  const double size = std::max({p.dims[0], p.dims[1], p.dims[2]});
  std::mt19937_64 rng(seed);
  for (const std::size_t end = out.size() + count; out.size() < end;) {
    Vec3 q;
    for (int a = 0; a < 3; ++a)
      q[a] = std::uniform_real_distribution<double>(b.lo[a] - 1, b.hi[a] + 1)(rng);
    if (std::fabs(p.signed_distance(q[0], q[1], q[2])) > 0.01 * size) out.push_back(q);
  }
}

// Points where the solid and the rendering must agree: towards every vertex just inside it and
// towards every edge's middle just outside it (half-way between the two circles), at mid-height;
// then random points in the bounds that are not within 1 % of the size of the surface.
std::vector<Vec3> probe_points(const Primitive3D& p) {
  std::vector<Vec3> out;
  const double r = 0.5 * (p.dims[0] + (p.kind == PrimitiveKind3D::Cone ? p.dims[1] : p.dims[0]));
  const double half = kPi / p.sides, between = 0.5 * r * (1 + std::cos(half));
  for (int i = 0; i < p.sides; ++i) {
    const double a = 2 * kPi * i / p.sides;
    out.push_back(model_point(p, {0.97 * r * std::cos(a), 0.97 * r * std::sin(a), 0}));
    out.push_back(model_point(p, {between * std::cos(a + half), between * std::sin(a + half), 0}));
  }
  add_random_probes(p, 200, 9, out);
  return out;
}

TEST_F(ScadPolygonRender, RenderedSolidHasThePrimitivesVolumeAndPoints) {
  auto polygonal = [](Primitive3D p, int sides) {
    p.sides = sides;
    return p;
  };
  const Primitive3D shapes[] = {
      // A nut trap tilted and turned about its axis; an octagonal frustum; a square pyramid.
      polygonal(Primitive3D::cylinder(2, -1, 3, 3, 5, Quaternion::from_euler_deg(20, -30, 40)), 6),
      polygonal(Primitive3D::cone(0, 0, 0, 4, 2, 6, Quaternion::from_euler_deg(-50, 10, 15)), 8),
      polygonal(Primitive3D::cone(1, 1, 1, 3, 0, 4, Quaternion::from_axis_angle(0, 0, 1, 10)), 4),
      polygonal(Primitive3D::cylinder(0, 0, 0, 5, 2, Quaternion::from_euler_deg(0, 90, 7)), 3),
  };
  int n = 0;
  for (const Primitive3D& p : shapes)
    expect_rendered_as_solved(p, "shape_" + std::to_string(n++), 1e-4, probe_points(p));
}

// Points where a rounded box and its rendering must agree: just inside each flat's middle and
// each arc's middle, just outside each arc's middle and inside the corner of the box it rounds,
// at mid-height and near the ends; then random points off the surface.
std::vector<Vec3> rounded_box_probes(const Primitive3D& p) {
  std::vector<Vec3> out;
  const double a = p.dims[0] / 2, b = p.dims[1] / 2, h = p.dims[2] / 2, r = p.corner;
  const double diagonal = 1 / std::sqrt(2.0);
  for (double z : {0.0, 0.9 * h, -0.9 * h}) {
    for (double sx : {-1.0, 1.0}) {
      out.push_back(model_point(p, {sx * 0.97 * a, 0, z}));
      out.push_back(model_point(p, {0, sx * 0.97 * b, z}));
      for (double sy : {-1.0, 1.0}) {
        const double cx = sx * (a - r), cy = sy * (b - r);
        for (double reach : {0.97 * r, 1.03 * r})
          out.push_back(model_point(p, {cx + sx * reach * diagonal, cy + sy * reach * diagonal, z}));
        out.push_back(model_point(p, {sx * (a - 0.1 * r), sy * (b - 0.1 * r), z}));
      }
    }
  }
  add_random_probes(p, 150, 13, out);
  return out;
}

TEST_F(ScadPolygonRender, RenderedRoundedBoxHasItsVolumeAndPoints) {
  const Primitive3D shapes[] = {
      // Tilted; a stadium turned about z; a disc; a block with small corners.
      Primitive3D::rounded_box(2, -1, 3, 20, 10, 4, 3, Quaternion::from_euler_deg(20, -30, 40)),
      Primitive3D::rounded_box(0, 0, 0, 12, 5, 3, 2.5, Quaternion::from_axis_angle(0, 0, 1, 25)),
      Primitive3D::rounded_box(1, 1, 1, 6, 6, 2, 3),
      Primitive3D::rounded_box(0, 0, 0, 8, 6, 5, 0.4, Quaternion::from_euler_deg(0, 90, 7)),
  };
  int n = 0;
  for (const Primitive3D& p : shapes)
    expect_rendered_as_solved(p, "rounded_" + std::to_string(n++), 1e-5, rounded_box_probes(p));
}

}  // namespace
}  // namespace csgfit
