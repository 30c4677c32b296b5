// Voxelisation and mesh diagnostics: volumes against analytic ones for closed, open,
// inverted, non-manifold, self-intersecting and inconsistently oriented meshes.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/model/mesh.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/model/voxelize.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Axis-aligned box [lo, hi], 12 outward triangles (vertex index x + 2y + 4z).
TriangleMesh box(std::array<double, 3> lo, std::array<double, 3> hi) {
  static const int kTriangles[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                        {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                        {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  TriangleMesh m;
  for (int v = 0; v < 8; ++v) {
    m.vertices.push_back({(v & 1) ? hi[0] : lo[0], (v & 2) ? hi[1] : lo[1], (v & 4) ? hi[2] : lo[2]});
  }
  for (const auto& t : kTriangles) m.triangles.push_back({t[0], t[1], t[2]});
  return m;
}

TriangleMesh unite(TriangleMesh a, const TriangleMesh& b) {
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return a;
}

TriangleMesh inverted(TriangleMesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// UV sphere: `slices` around z, `stacks` from pole to pole; 2 * slices * (stacks - 1) triangles.
TriangleMesh sphere(double r, int slices, int stacks, std::array<double, 3> c = {0, 0, 0}) {
  TriangleMesh m;
  m.vertices.push_back({c[0], c[1], c[2] - r});
  for (int i = 1; i < stacks; ++i) {
    const double phi = -kPi / 2 + kPi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double th = 2 * kPi * j / slices;
      m.vertices.push_back({c[0] + r * std::cos(phi) * std::cos(th), c[1] + r * std::cos(phi) * std::sin(th),
                            c[2] + r * std::sin(phi)});
    }
  }
  m.vertices.push_back({c[0], c[1], c[2] + r});
  const int top = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [slices](int i, int j) { return 1 + (i - 1) * slices + (j % slices); };
  for (int j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      m.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  }
  for (int j = 0; j < slices; ++j) m.triangles.push_back({top, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
  return m;
}

double voxel_volume(const VoxelGrid& g) {
  return static_cast<double>(g.count()) * g.voxel_size() * g.voxel_size() * g.voxel_size();
}

// Volume within one voxel layer over the surface: |V_vox - V| <= area * h (typically far less).
void expect_volume(const VoxelGrid& g, double volume, double area, double layers = 1.0) {
  EXPECT_NEAR(voxel_volume(g), volume, layers * area * g.voxel_size())
      << "voxels " << g.count() << " of size " << g.voxel_size();
}

TEST(VoxelizeTest, UnitCubeIsExactAndWatertightOnEdges) {
  // Voxel centres fall exactly on the faces' diagonals here: each must count once.
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(box({0, 0, 0}, {1, 1, 1}), {}, &stats);
  EXPECT_EQ(g.nx(), 98);  // 96 + a margin of one voxel on each side
  EXPECT_NEAR(g.voxel_size(), 1.0 / 96, 1e-15);
  EXPECT_EQ(g.count(), 96u * 96u * 96u);
  EXPECT_EQ(stats.ambiguous_voxels, 0u);
  EXPECT_FALSE(g.get(0, 50, 50));
  EXPECT_TRUE(g.get(1, 50, 50));
  VoxelizeOptions o;
  o.voxel_size = 0.125;
  o.margin = 2;
  const VoxelGrid h = voxelize(box({0, 0, 0}, {1, 1, 1}), o);
  EXPECT_EQ(h.nx(), 12);
  EXPECT_EQ(h.count(), 512u);
}

TEST(VoxelizeTest, RaysThroughVerticesAndEdges) {
  // With an odd resolution the middle z-row passes exactly through both poles of the sphere,
  // where 48 triangles meet, and the x-rows at y = 0 run along the meridian edges at angle 0.
  // The edge rule must count each such crossing once: a double or missed count would flip
  // the whole row.
  const TriangleMesh s = sphere(1, 48, 24);
  VoxelizeOptions o;
  o.resolution = 95;
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(s, o, &stats);
  ASSERT_EQ(g.nx(), 97);
  EXPECT_EQ(g.center_x(48), 0.0);
  EXPECT_EQ(g.center_y(48), 0.0);
  EXPECT_EQ(stats.ambiguous_voxels, 0u);
  for (int k = 0; k < g.nz(); ++k) {
    const double z = g.center_z(k);
    if (std::abs(z) < 0.98) EXPECT_TRUE(g.get(48, 48, k)) << k;
    if (std::abs(z) > 1.0) EXPECT_FALSE(g.get(48, 48, k)) << k;
  }
  for (int i = 0; i < g.nx(); ++i) {
    const double x = g.center_x(i);
    if (std::abs(x) < 0.98) EXPECT_TRUE(g.get(i, 48, 48)) << i;
    if (std::abs(x) > 1.0) EXPECT_FALSE(g.get(i, 48, 48)) << i;
  }
  expect_volume(g, signed_volume(s), analyze_mesh(s).surface_area, 0.5);
}

TEST(VoxelizeTest, TetrahedronAndSphereVolumes) {
  TriangleMesh tet;
  tet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  expect_volume(voxelize(tet), 1.0 / 6, 1.5 + std::sqrt(3.0) / 2, 0.5);
  const TriangleMesh s = sphere(1.0, 64, 32, {0.3, -2, 5});
  const MeshReport r = analyze_mesh(s);
  EXPECT_TRUE(r.watertight());
  EXPECT_NEAR(r.signed_volume, 4.0 / 3 * kPi, 0.05);
  expect_volume(voxelize(s), r.signed_volume, r.surface_area, 0.5);
}

TEST(VoxelizeTest, InvertedMeshGivesTheSameSolid) {
  const TriangleMesh c = box({0, 0, 0}, {2, 1, 1});
  const MeshReport r = analyze_mesh(inverted(c));
  EXPECT_TRUE(r.inverted());
  EXPECT_TRUE(r.watertight());
  EXPECT_NE(describe_mesh_problems(r).find("inward"), std::string::npos);
  EXPECT_EQ(voxelize(inverted(c)), voxelize(c));
  const TriangleMesh s = sphere(1, 40, 20);
  EXPECT_EQ(voxelize(inverted(s)), voxelize(s));
  EXPECT_NEAR(winding_number(c, {1, 0.5, 0.5}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(inverted(c), {1, 0.5, 0.5}), -1.0, 1e-12);
  EXPECT_NEAR(winding_number(c, {3, 0.5, 0.5}), 0.0, 1e-12);
}

TEST(VoxelizeTest, OpenCubeMissingOneFace) {
  TriangleMesh open = box({0, 0, 0}, {1, 1, 1});
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);  // the top face
  const MeshReport r = analyze_mesh(open);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_FALSE(r.closed());
  const std::string why = describe_mesh_problems(r);
  EXPECT_NE(why.find("open: 4 boundary edges"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos);
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(open, {}, &stats);
  expect_volume(g, 1.0, 6.0, 0.5);
  // Nothing above the hole.
  EXPECT_FALSE(g.get(50, 50, g.nz() - 1));
}

TEST(VoxelizeTest, SphereWithAHole) {
  // Remove the top cap (every triangle touching the north pole) and one band of the side.
  TriangleMesh s = sphere(1, 48, 24);
  const int top = static_cast<int>(s.vertices.size()) - 1;
  TriangleMesh open = s;
  open.triangles.clear();
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const bool cap = tri[0] == top || tri[1] == top || tri[2] == top;
    if (!cap && !(t >= 600 && t < 640)) open.triangles.push_back(tri);
  }
  const MeshReport r = analyze_mesh(open);
  EXPECT_GT(r.boundary_edges, 0u);
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(open, {}, &stats);
  const VoxelGrid full = voxelize(s);
  // Up to a few voxel layers near the holes may differ.
  EXPECT_LT(static_cast<double>(count_xor(g, full)), 0.02 * static_cast<double>(full.count()))
      << "ambiguous " << stats.ambiguous_voxels << ", winding " << stats.winding_evaluations;
}

TEST(VoxelizeTest, NonManifoldCubesSharingAnEdge) {
  const TriangleMesh m = unite(box({0, 0, 0}, {1, 1, 1}), box({1, 1, 0}, {2, 2, 1}));
  const MeshReport r = analyze_mesh(m);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_NE(describe_mesh_problems(r).find("non-manifold"), std::string::npos);
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(m, {}, &stats);
  expect_volume(g, 2.0, 12.0, 0.25);
  EXPECT_EQ(g.count() % 1, 0u);
}

TEST(VoxelizeTest, SelfIntersectingSoupGivesTheUnion) {
  const TriangleMesh m = unite(box({0, 0, 0}, {2, 2, 2}), box({1, 1, 1}, {3, 3, 3}));
  const MeshReport r = analyze_mesh(m);
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.components, 2u);
  const VoxelGrid g = voxelize(m);
  expect_volume(g, 15.0, 2 * 24.0 - 6.0, 0.25);
  // Also when one of the two is inverted.
  expect_volume(voxelize(unite(box({0, 0, 0}, {2, 2, 2}), inverted(box({1, 1, 1}, {3, 3, 3})))), 15.0,
                42.0, 0.25);
}

TEST(VoxelizeTest, CavityIsKept) {
  // Outer shell outward, inner shell inward: a hollow box.
  const TriangleMesh m = unite(box({0, 0, 0}, {3, 3, 3}), inverted(box({1, 1, 1}, {2, 2, 2})));
  const MeshReport r = analyze_mesh(m);
  EXPECT_TRUE(r.watertight());
  EXPECT_NEAR(r.signed_volume, 26.0, 1e-9);
  const VoxelGrid g = voxelize(m);
  expect_volume(g, 26.0, 60.0, 0.25);
  EXPECT_FALSE(g.get(g.nx() / 2, g.ny() / 2, g.nz() / 2));
}

TEST(VoxelizeTest, InconsistentOrientationIsRepaired) {
  TriangleMesh m = sphere(1, 32, 16);
  for (std::size_t t = 0; t < m.triangles.size(); t += 7) std::swap(m.triangles[t][1], m.triangles[t][2]);
  const MeshReport r = analyze_mesh(m);
  EXPECT_GT(r.inconsistent_edges, 0u);
  EXPECT_NE(describe_mesh_problems(r).find("disagree on orientation"), std::string::npos);
  TriangleMesh fixed = m;
  EXPECT_EQ(repair_orientation(fixed), (m.triangles.size() + 6) / 7);
  EXPECT_TRUE(analyze_mesh(fixed).watertight());
  VoxelizeStats stats;
  EXPECT_EQ(voxelize(m, {}, &stats), voxelize(sphere(1, 32, 16)));
  EXPECT_EQ(stats.orientation_flips, (m.triangles.size() + 6) / 7);
}

TEST(VoxelizeTest, WeldVertices) {
  TriangleMesh soup;
  const TriangleMesh c = box({0, 0, 0}, {1, 1, 1});
  for (const auto& t : c.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int v : t) soup.vertices.push_back(c.vertices[v]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_TRUE(analyze_mesh(soup).watertight());  // analysis welds by position itself
  EXPECT_EQ(weld_vertices(soup), 36u - 8u);
  EXPECT_EQ(soup.vertices.size(), 8u);
  EXPECT_TRUE(analyze_mesh(soup).watertight());
}

TEST(VoxelizeTest, FastEnoughAt96WithTenThousandTriangles) {
  const TriangleMesh s = sphere(1, 100, 51);  // 10,000 triangles
  ASSERT_EQ(s.triangles.size(), 10000u);
  VoxelizeStats stats;
  const VoxelGrid g = voxelize(s, {}, &stats);
  std::printf("[ timing   ] voxelize 96^3, 10k triangles: %.3f s\n", stats.seconds);
  EXPECT_LT(stats.seconds, 5.0);  // ~0.02 s in Release; loose for sanitizer builds
  expect_volume(g, signed_volume(s), analyze_mesh(s).surface_area, 0.5);

  // An open version with many split votes must stay bounded by the winding budget.
  TriangleMesh half = s;
  half.triangles.resize(half.triangles.size() / 2);
  const auto t0 = std::chrono::steady_clock::now();
  voxelize(half, {}, &stats);
  const double open_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ timing   ] open half sphere: %.3f s, %zu split votes, %zu winding numbers\n",
              open_seconds, stats.ambiguous_voxels, stats.winding_evaluations);
  EXPECT_LT(open_seconds, 30.0);
}

// lattice_shift moves the centres by a fraction of a voxel and nothing else: same size, same
// voxel edge, and the same solid seen from between the first lattice's rows.
TEST(VoxelizeTest, StaggeredLatticeIsShiftedByHalfAVoxel) {
  // 2.04 x 1.04 x 1.04 on 0.1 voxels: the first lattice's centres lie 0.02 inside the faces
  // (21 x 11 x 11 of them), the staggered one's 0.07 inside (20 x 10 x 10); no centre on a face.
  const TriangleMesh m = box({0, 0, 0}, {2.04, 1.04, 1.04});
  VoxelizeOptions o;
  o.voxel_size = 0.1;
  VoxelizeOptions s = o;
  s.lattice_shift = 0.5;
  const VoxelGrid a = voxelize(m, o), b = voxelize(m, s);
  EXPECT_EQ(a.nx(), b.nx());
  EXPECT_EQ(a.ny(), b.ny());
  EXPECT_EQ(a.nz(), b.nz());
  EXPECT_NEAR(b.origin_x() - a.origin_x(), 0.05, 1e-12);
  EXPECT_NEAR(b.origin_y() - a.origin_y(), 0.05, 1e-12);
  EXPECT_NEAR(b.origin_z() - a.origin_z(), 0.05, 1e-12);
  EXPECT_EQ(a.count(), 21u * 11 * 11);
  EXPECT_EQ(b.count(), 20u * 10 * 10);
  for (double bad : {-0.1, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    VoxelizeOptions w = o;
    w.lattice_shift = bad;
    EXPECT_THROW(voxelize(m, w), InputError);
  }
}

TEST(VoxelizeTest, BadInput) {
  auto message = [](const TriangleMesh& m, const VoxelizeOptions& o) -> std::string {
    try {
      voxelize(m, o);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message(TriangleMesh{}, {}).find("no triangles"), std::string::npos);
  TriangleMesh nan = box({0, 0, 0}, {1, 1, 1});
  nan.vertices[3][0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(nan, {}).find("non-finite"), std::string::npos);
  TriangleMesh bad = box({0, 0, 0}, {1, 1, 1});
  bad.triangles[0][0] = 99;
  EXPECT_NE(message(bad, {}).find("out of range"), std::string::npos);
  VoxelizeOptions tiny;
  tiny.voxel_size = 1e-6;
  EXPECT_NE(message(box({0, 0, 0}, {1, 1, 1}), tiny).find("limit"), std::string::npos);
  VoxelizeOptions zero;
  zero.resolution = 0;
  EXPECT_NE(message(box({0, 0, 0}, {1, 1, 1}), zero).find("resolution"), std::string::npos);
  TriangleMesh point;
  point.vertices = {{1, 1, 1}};
  point.triangles = {{0, 0, 0}};
  EXPECT_NE(message(point, {}).find("no extent"), std::string::npos);
}

TEST(VoxelizeTest, BenchmarkMeshesAreClosedAndVoxeliseToTheirVolume) {
  const std::string root = "/work/shared/benchmarks/3d/inversecsg/";
  int done = 0;
  for (const char* id : {"011", "041", "056"}) {
    const std::string path = root + id + "/csg_high_res.off";
    if (!std::filesystem::exists(path)) continue;
    SCOPED_TRACE(path);
    const TriangleMesh m = read_mesh(path);
    const MeshReport r = analyze_mesh(m);
    EXPECT_TRUE(r.closed()) << describe_mesh_problems(r);
    EXPECT_GT(r.signed_volume, 0);
    VoxelizeStats stats;
    const VoxelGrid g = voxelize(m, {}, &stats);
    std::printf("[ bench    ] %s: %zu triangles, volume %.4f, voxels %.4f, %.3f s, %zu split votes\n",
                id, m.triangles.size(), r.signed_volume, voxel_volume(g), stats.seconds,
                stats.ambiguous_voxels);
    expect_volume(g, std::abs(r.signed_volume), r.surface_area, 0.25);
    // Thin parts (011 is a rod 8 voxels across) put a few percent in one voxel layer.
    EXPECT_NEAR(voxel_volume(g) / std::abs(r.signed_volume), 1.0, 0.1);
    ++done;
  }
  if (done == 0) GTEST_SKIP() << "benchmark meshes not found under " << root;
}

}  // namespace
}  // namespace csgfit
