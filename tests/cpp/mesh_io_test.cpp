// Mesh and voxel grid readers: every format on fixtures written here, and every bad input.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/model/mesh.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "scratch_dir.h"

namespace csgfit {
namespace {

namespace fs = std::filesystem;

// A cube [0, s]^3 as 8 vertices (index x + 2y + 4z) and 12 outward triangles; QUADS are its
// faces as quads, fanned from their first vertex into those triangles.
const int kCubeTriangles[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
const int kCubeQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                              {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

TriangleMesh cube(double s) {
  TriangleMesh m;
  for (int v = 0; v < 8; ++v) m.vertices.push_back({s * (v & 1), s * ((v >> 1) & 1), s * ((v >> 2) & 1)});
  for (const auto& t : kCubeTriangles) m.triangles.push_back({t[0], t[1], t[2]});
  return m;
}

TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

std::string stl_ascii(const TriangleMesh& m) {
  std::string s = "solid test\n";
  for (const auto& t : m.triangles) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (int v : t) {
      const auto& p = m.vertices[v];
      s += "      vertex " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " +
           std::to_string(p[2]) + "\n";
    }
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid test\n";
}

void put_le32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}
void put_float(std::string& s, float f, bool big = false) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  for (int i = 0; i < 4; ++i) s += static_cast<char>((bits >> (8 * (big ? 3 - i : i))) & 0xFF);
}
void put_double(std::string& s, double d, bool big = false) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  for (int i = 0; i < 8; ++i) s += static_cast<char>((bits >> (8 * (big ? 7 - i : i))) & 0xFF);
}
void put_int(std::string& s, std::uint64_t v, int bytes, bool big = false) {
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * (big ? bytes - 1 - i : i))) & 0xFF);
}

// Binary STL whose 80-byte header starts with "solid", as many exporters write it.
std::string stl_binary(const TriangleMesh& m, long long declared = -1) {
  std::string s = "solid but actually binary";
  s.resize(80, ' ');
  put_le32(s, static_cast<std::uint32_t>(declared < 0 ? static_cast<long long>(m.triangles.size()) : declared));
  for (const auto& t : m.triangles) {
    for (int i = 0; i < 3; ++i) put_float(s, 0);
    for (int v : t) {
      for (double c : m.vertices[v]) put_float(s, static_cast<float>(c));
    }
    s += std::string(2, '\0');
  }
  return s;
}

std::string obj_quads_cube(double s) {
  std::string o = "# cube\nmtllib x.mtl\no cube\ng side\n";
  for (int v = 0; v < 8; ++v) {
    o += "v " + std::to_string(s * (v & 1)) + " " + std::to_string(s * ((v >> 1) & 1)) + " " +
         std::to_string(s * ((v >> 2) & 1)) + "\n";
  }
  o += "vt 0 0\nvt 1 0\nvn 0 0 1\ns off\nusemtl m\n";
  for (int f = 0; f < 6; ++f) {
    o += "f";
    for (int k = 0; k < 4; ++k) {
      const int i = kCubeQuads[f][k] + 1;
      // Mix the index forms, and negative (relative) indices on the last face.
      if (f == 5) o += " " + std::to_string(i - 9);
      else if (k == 0) o += " " + std::to_string(i) + "/1/1";
      else if (k == 1) o += " " + std::to_string(i) + "//1";
      else o += " " + std::to_string(i) + "/2";
    }
    o += "\n";
  }
  return o;
}

std::string obj_tri(const TriangleMesh& m) {
  std::string o;
  for (const auto& p : m.vertices) {
    o += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  }
  for (const auto& t : m.triangles) {
    o += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
         std::to_string(t[2] + 1) + "\n";
  }
  return o;
}

std::string off_quads_cube(double s) {
  std::string o = "# a comment before the header\nOFF\n# counts\n8 6 12\n";
  for (int v = 0; v < 8; ++v) {
    o += std::to_string(s * (v & 1)) + " " + std::to_string(s * ((v >> 1) & 1)) + " " +
         std::to_string(s * ((v >> 2) & 1)) + "   # vertex " + std::to_string(v) + "\n";
  }
  o += "\n";
  for (const auto& q : kCubeQuads) {
    o += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) +
         " " + std::to_string(q[3]) + " 255 0 0\n";  // trailing face colour
  }
  return o;
}

std::string off_tri(const TriangleMesh& m) {
  std::string o = "OFF " + std::to_string(m.vertices.size()) + " " + std::to_string(m.triangles.size()) + " 0\n";
  for (const auto& p : m.vertices) {
    o += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  }
  for (const auto& t : m.triangles) {
    o += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  }
  return o;
}

enum class PlyKind { kAscii, kLittle, kBig };

// PLY with extra properties and elements the reader must skip: a colour per vertex, a
// per-face flag, and an unknown element with a list before and after the faces.
std::string ply(const TriangleMesh& m, PlyKind kind, bool quads_cube = false, bool edges = true) {
  const bool big = kind == PlyKind::kBig;
  std::string h = "ply\nformat ";
  h += kind == PlyKind::kAscii ? "ascii" : big ? "binary_big_endian" : "binary_little_endian";
  h += " 1.0\ncomment written by mesh_io_test\n";
  h += "element material 2\nproperty uchar id\nproperty list uchar float weights\n";
  h += "element vertex " + std::to_string(m.vertices.size()) + "\n";
  if (kind == PlyKind::kLittle) {
    h += "property double x\nproperty double y\nproperty uchar red\nproperty double z\n";
  } else {
    h += "property float x\nproperty float y\nproperty float z\nproperty ushort red\n";
  }
  const std::size_t faces = quads_cube ? 6 : m.triangles.size();
  h += "element face " + std::to_string(faces) + "\nproperty uchar flags\n";
  h += big ? "property list int uint vertex_index\n" : "property list uchar int vertex_indices\n";
  if (edges) h += "element edge 1\nproperty int vertex1\nproperty int vertex2\n";
  h += "end_header\n";
  std::string b;
  std::vector<std::vector<int>> face_list;
  if (quads_cube) {
    for (const auto& q : kCubeQuads) face_list.push_back({q[0], q[1], q[2], q[3]});
  } else {
    for (const auto& t : m.triangles) face_list.push_back({t[0], t[1], t[2]});
  }
  if (kind == PlyKind::kAscii) {
    b += "1 2 0.5 0.25\n2 0\n";
    for (const auto& p : m.vertices) {
      b += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + " 7\n";
    }
    for (const auto& f : face_list) {
      b += "0 " + std::to_string(f.size());
      for (int v : f) b += " " + std::to_string(v);
      b += "\n";
    }
    if (edges) b += "0 1\n";
  } else {
    put_int(b, 1, 1);
    put_int(b, 2, 1);
    put_float(b, 0.5f, big);
    put_float(b, 0.25f, big);
    put_int(b, 2, 1);
    put_int(b, 0, 1);
    for (const auto& p : m.vertices) {
      if (kind == PlyKind::kLittle) {
        put_double(b, p[0]);
        put_double(b, p[1]);
        put_int(b, 7, 1);
        put_double(b, p[2]);
      } else {
        for (double c : p) put_float(b, static_cast<float>(c), true);
        put_int(b, 7, 2, true);
      }
    }
    for (const auto& f : face_list) {
      put_int(b, 0, 1);
      if (big) put_int(b, f.size(), 4, true);
      else put_int(b, f.size(), 1);
      for (int v : f) put_int(b, static_cast<std::uint64_t>(v), 4, big);
    }
    if (edges) {
      put_int(b, 0, 4, big);
      put_int(b, 1, 4, big);
    }
  }
  return h + b;
}

std::string png_bytes() {
  std::string s = "\x89PNG\r\n\x1a\n";
  s += std::string("\0\0\0\rIHDR\0\0\0\x10\0\0\0\x10\x08\x00\0\0\0", 21);
  s.resize(200, '\x11');
  return s;
}

class MeshIoTest : public testing::ScratchDirTest {
 protected:

  // The InputError message of f, checked to be one line naming the file.
  std::string error_of(const std::function<void()>& f, const std::string& path = "") {
    try {
      f();
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      if (!path.empty()) EXPECT_NE(m.find(path), std::string::npos) << "message does not name the file: " << m;
      return m;
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": not an InputError: " << e.what();
      return "";
    }
    ADD_FAILURE() << path << ": no error";
    return "";
  }

  void expect_mesh_error(const std::string& path, const std::string& word,
                         const MeshReadOptions& options = {}) {
    const std::string m = error_of([&] { read_mesh(path, options); }, path);
    EXPECT_NE(m.find(word), std::string::npos) << "expected '" << word << "' in: " << m;
  }

  void expect_voxel_error(const std::string& path, const std::string& word) {
    const std::string m = error_of([&] { read_voxels(path); }, path);
    EXPECT_NE(m.find(word), std::string::npos) << "expected '" << word << "' in: " << m;
  }
};

void expect_solid(const TriangleMesh& m, std::size_t vertices, std::size_t triangles, double volume) {
  EXPECT_EQ(m.vertices.size(), vertices);
  EXPECT_EQ(m.triangles.size(), triangles);
  const MeshReport r = analyze_mesh(m);
  EXPECT_TRUE(r.watertight()) << r.boundary_edges << " " << r.non_manifold_edges << " " << r.inconsistent_edges;
  EXPECT_EQ(r.components, 1u);
  EXPECT_NEAR(r.signed_volume, volume, 1e-5);
  EXPECT_EQ(describe_mesh_problems(r), "");
}

TEST_F(MeshIoTest, ReadsCubeAndTetrahedronInEveryFormat) {
  const TriangleMesh c = cube(2), t = tetrahedron();
  struct Case {
    std::string name, bytes, format;
    std::size_t vertices, triangles;
    double volume;
  };
  const std::vector<Case> cases = {
      {"cube.stl", stl_ascii(c), "STL (ASCII)", 8, 12, 8},
      {"tet.stl", stl_ascii(t), "STL (ASCII)", 4, 4, 1.0 / 6},
      {"cube_bin.STL", stl_binary(c), "STL (binary)", 8, 12, 8},
      {"tet_bin.stl", stl_binary(t), "STL (binary)", 4, 4, 1.0 / 6},
      {"cube.obj", obj_quads_cube(2), "OBJ", 8, 12, 8},
      {"tet.obj", obj_tri(t), "OBJ", 4, 4, 1.0 / 6},
      {"cube.off", off_quads_cube(2), "OFF", 8, 12, 8},
      {"tet.off", off_tri(t), "OFF", 4, 4, 1.0 / 6},
      {"cube_a.ply", ply(c, PlyKind::kAscii, true), "PLY (ascii)", 8, 12, 8},
      {"tet_a.ply", ply(t, PlyKind::kAscii), "PLY (ascii)", 4, 4, 1.0 / 6},
      {"cube_le.ply", ply(c, PlyKind::kLittle, true), "PLY (binary little-endian)", 8, 12, 8},
      {"tet_le.ply", ply(t, PlyKind::kLittle), "PLY (binary little-endian)", 4, 4, 1.0 / 6},
      {"cube_be.ply", ply(c, PlyKind::kBig, true), "PLY (binary big-endian)", 8, 12, 8},
      {"tet_be.ply", ply(t, PlyKind::kBig), "PLY (binary big-endian)", 4, 4, 1.0 / 6},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    MeshReadInfo info;
    const TriangleMesh m = read_mesh(file(k.name, k.bytes), {}, &info);
    EXPECT_EQ(info.format, k.format);
    EXPECT_EQ(info.degenerate_dropped, 0u);
    expect_solid(m, k.vertices, k.triangles, k.volume);
  }
}

TEST_F(MeshIoTest, AsciiStlVariants) {
  // Upper case keywords, several solids, CRLF line ends.
  std::string s = stl_ascii(tetrahedron());
  std::string upper;
  for (char ch : s) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  std::string crlf;
  for (char ch : s + s) {
    if (ch == '\n') crlf += '\r';
    crlf += ch;
  }
  expect_solid(read_mesh(file("upper.stl", upper)), 4, 4, 1.0 / 6);
  const TriangleMesh two = read_mesh(file("two.stl", crlf));
  EXPECT_EQ(two.triangles.size(), 8u);  // welded: the same tetrahedron twice
  EXPECT_EQ(two.vertices.size(), 4u);
}

TEST_F(MeshIoTest, DropsAndCountsDegenerateTriangles) {
  std::string o = obj_tri(cube(1));
  o += "f 1 1 2\n";        // repeated vertex
  o += "v 0.5 0 0\nf 1 2 9\n";  // collinear
  MeshReadInfo info;
  const TriangleMesh m = read_mesh(file("deg.obj", o), {}, &info);
  EXPECT_EQ(info.degenerate_dropped, 2u);
  EXPECT_EQ(info.faces_read, 14u);
  EXPECT_EQ(m.triangles.size(), 12u);
}

TEST_F(MeshIoTest, MissingEmptyAndUnknown) {
  expect_mesh_error(dir_ + "/nope.stl", "cannot open");
  expect_mesh_error(file("empty.stl", ""), "empty");
  expect_mesh_error(file("empty.ply", ""), "empty");
  expect_mesh_error(file("mesh.3ds", "abc"), "unknown mesh format");
  expect_mesh_error(dir_, "unknown mesh format");
  const std::string d = dir_ + "/dir.stl";
  fs::create_directory(d);
  expect_mesh_error(d, "cannot open");
  expect_voxel_error(dir_ + "/nope.npy", "cannot open");
  expect_voxel_error(file("grid.raw", "abc"), "unknown voxel grid format");
}

TEST_F(MeshIoTest, Truncated) {
  const TriangleMesh c = cube(1);
  std::string bin = stl_binary(c);
  bin.resize(bin.size() - 30);
  expect_mesh_error(file("cut.stl", bin), "truncated");
  std::string bin_plain = stl_binary(c);
  bin_plain.replace(0, 5, "BINAR");  // header not starting with "solid"
  bin_plain.resize(bin_plain.size() - 50);
  expect_mesh_error(file("cut2.stl", bin_plain), "truncated");
  std::string ascii = stl_ascii(c);
  expect_mesh_error(file("cut.stl", ascii.substr(0, ascii.size() / 2)), "truncated");
  expect_mesh_error(file("noend.stl", ascii.substr(0, ascii.find("endsolid"))), "truncated");
  std::string off = off_quads_cube(1);
  expect_mesh_error(file("cut.off", off.substr(0, off.rfind("4 "))), "truncated");
  expect_mesh_error(file("cutv.off", "OFF\n8 6 0\n0 0 0\n1 1 1\n"), "truncated");
  for (PlyKind kind : {PlyKind::kAscii, PlyKind::kLittle, PlyKind::kBig}) {
    std::string p = ply(c, kind, false, false);
    // Fewer faces than declared: cut inside the face data, and right after the vertices.
    expect_mesh_error(file("cut.ply", p.substr(0, p.size() - 20)), "truncated");
    std::string more = p;
    more.replace(more.find("element face 12"), 15, "element face 13");
    expect_mesh_error(file("more.ply", more), "truncated");
    std::string morev = p;
    morev.replace(morev.find("element vertex 8"), 16, "element vertex 9");
    expect_mesh_error(file("morev.ply", morev), "truncated");
  }
  expect_mesh_error(file("noheader.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), "truncated");
}

TEST_F(MeshIoTest, Mislabelled) {
  const std::string png = png_bytes();
  for (const char* name : {"img.stl", "img.obj", "img.off", "img.ply"}) {
    SCOPED_TRACE(name);
    expect_mesh_error(file(name, png), "PNG");
  }
  expect_voxel_error(file("img.npy", png), "PNG");
  expect_voxel_error(file("img.binvox", png), "PNG");
  expect_mesh_error(file("ply.stl", ply(cube(1), PlyKind::kLittle)), "PLY");
  expect_mesh_error(file("off.obj", off_tri(cube(1))), "OFF");
  expect_mesh_error(file("stl.off", stl_ascii(cube(1))), "STL");
  expect_mesh_error(file("stl.ply", stl_ascii(cube(1))), "STL");
  expect_mesh_error(file("text.ply", "hello\n"), "not a PLY");
  expect_mesh_error(file("bin.obj", std::string("v 0 0 0\n\0\x01\x02", 11)), "binary");
  expect_mesh_error(file("text.stl", "just some text that is long enough to be mistaken for a binary stl "
                                     "header if one only checked the size of the file at all"),
                    "STL");
}

TEST_F(MeshIoTest, NonFiniteCoordinates) {
  std::string o = obj_tri(tetrahedron());
  o.replace(o.find("v 1.000000"), 10, "v nan");
  expect_mesh_error(file("nan.obj", o), "non-finite");
  std::string inf = obj_tri(tetrahedron());
  inf.replace(inf.find("v 1.000000"), 10, "v -inf");
  expect_mesh_error(file("inf.obj", inf), "non-finite");
  TriangleMesh t = tetrahedron();
  t.vertices[2][1] = std::numeric_limits<double>::quiet_NaN();
  expect_mesh_error(file("nan.stl", stl_binary(t)), "non-finite");
  expect_mesh_error(file("nan_a.stl", stl_ascii(t)), "non-finite");
  expect_mesh_error(file("nan.off", off_tri(t)), "non-finite");
  for (PlyKind kind : {PlyKind::kAscii, PlyKind::kLittle, PlyKind::kBig}) {
    expect_mesh_error(file("nan.ply", ply(t, kind)), "non-finite");
  }
}

TEST_F(MeshIoTest, FaceIndexOutOfRange) {
  expect_mesh_error(file("oor.obj", obj_tri(tetrahedron()) + "f 1 2 5\n"), "out of range");
  expect_mesh_error(file("oorneg.obj", obj_tri(tetrahedron()) + "f 1 2 -5\n"), "out of range");
  expect_mesh_error(file("zero.obj", obj_tri(tetrahedron()) + "f 0 1 2\n"), "bad face vertex");
  std::string off = off_tri(tetrahedron());
  off.replace(off.rfind("3 1 2 3"), 7, "3 1 2 4");
  expect_mesh_error(file("oor.off", off), "out of range");
  TriangleMesh t = tetrahedron();
  t.triangles[3][2] = 7;
  for (PlyKind kind : {PlyKind::kAscii, PlyKind::kLittle, PlyKind::kBig}) {
    expect_mesh_error(file("oor.ply", ply(t, kind)), "out of range");
  }
  t.triangles[3][2] = -1;
  expect_mesh_error(file("neg.ply", ply(t, PlyKind::kLittle)), "out of range");
}

TEST_F(MeshIoTest, NoTriangles) {
  expect_mesh_error(file("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no triangles");
  expect_mesh_error(file("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), "no triangles");
  expect_mesh_error(file("nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "no triangles");
  expect_mesh_error(file("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                      "property float y\nproperty float z\nend_header\n0 0 0\n"),
                    "no triangles");
  expect_mesh_error(file("empty_solid.stl", "solid x\nendsolid x\n"), "no triangles");
  std::string zero = stl_binary(cube(1), 0);
  zero.resize(84);
  expect_mesh_error(file("zero.stl", zero), "no triangles");
}

TEST_F(MeshIoTest, HugeDeclaredCountsFailFast) {
  const auto start = std::chrono::steady_clock::now();
  const std::string ply_head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\n";
  expect_mesh_error(file("huge.ply", ply_head + "element face 1000000000000\n"
                                                "property list uchar int vertex_indices\nend_header\n"),
                    "limit");
  expect_mesh_error(file("hugev.ply", "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\n"
                                      "property float y\nproperty float z\nend_header\n"),
                    "limit");
  // An unknown element with a huge count is skipped by size, failing as truncated at once.
  expect_mesh_error(file("hugeother.ply", ply(cube(1), PlyKind::kLittle).replace(
                                              ply(cube(1), PlyKind::kLittle).find("element edge 1"), 14,
                                              "element edge 999999999999")),
                    "truncated");
  expect_mesh_error(file("huge.off", "OFF\n3 1000000000000 0\n"), "limit");
  expect_mesh_error(file("hugev.off", "OFF\n1000000000000 1 0\n"), "limit");
  std::string stl = stl_binary(cube(1), 0xFFFFFFFFu);
  expect_mesh_error(file("huge.stl", stl), "limit");
  MeshReadOptions small;
  small.max_triangles = 10;
  expect_mesh_error(file("cube.obj", obj_tri(cube(1))), "limit", small);
  expect_mesh_error(file("cube.stl", stl_ascii(cube(1))), "limit", small);
  expect_mesh_error(file("cubeb.stl", stl_binary(cube(1))), "limit", small);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
}

TEST_F(MeshIoTest, GarbageNeverCrashes) {
  // Every prefix of each valid fixture either reads or fails with an InputError.
  const TriangleMesh c = cube(1);
  const std::vector<std::pair<std::string, std::string>> fixtures = {
      {"g.stl", stl_ascii(c)}, {"g.stl", stl_binary(c)}, {"g.obj", obj_quads_cube(1)},
      {"g.off", off_quads_cube(1)}, {"g.ply", ply(c, PlyKind::kAscii)},
      {"g.ply", ply(c, PlyKind::kLittle)}, {"g.ply", ply(c, PlyKind::kBig)}};
  for (const auto& [name, bytes] : fixtures) {
    for (std::size_t n = 0; n < bytes.size(); n += 7) {
      const std::string path = file(name, bytes.substr(0, n));
      try {
        read_mesh(path);
      } catch (const InputError&) {
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Voxel grids

std::string npy(const std::string& descr, bool fortran, const std::string& shape,
                const std::string& data, int version = 1) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                     ", 'shape': " + shape + ", }";
  const std::size_t pre = version == 1 ? 10 : 12;
  while ((pre + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string s = "\x93NUMPY";
  s += static_cast<char>(version);
  s += '\0';
  put_int(s, dict.size(), version == 1 ? 2 : 4);
  return s + dict + data;
}

bool pattern(int i, int j, int k) { return (i * 7 + j * 3 + k * 5) % 4 == 0 || (i == 2 && k == 4); }

TEST_F(MeshIoTest, ReadsNpyInEveryLayoutAndType) {
  const int s0 = 3, s1 = 4, s2 = 5;
  auto make = [&](bool fortran, int bytes, bool is_float, bool big) {
    std::string d;
    for (int n = 0; n < s0 * s1 * s2; ++n) {
      int i, j, k;
      if (fortran) {
        i = n % s0;
        j = (n / s0) % s1;
        k = n / (s0 * s1);
      } else {
        k = n % s2;
        j = (n / s2) % s1;
        i = n / (s1 * s2);
      }
      const bool v = pattern(i, j, k);
      if (is_float && bytes == 8) put_double(d, v ? 0.75 : 0.0, big);
      else if (is_float) put_float(d, v ? 2.0f : 0.0f, big);
      else put_int(d, v ? (bytes > 1 ? 256u : 1u) : 0u, bytes, big);  // 256: only a high byte set
    }
    return d;
  };
  struct Case {
    std::string descr;
    bool fortran;
    int bytes;
    bool is_float, big;
    int version;
  };
  const std::vector<Case> cases = {
      {"|b1", false, 1, false, false, 1}, {"|b1", true, 1, false, false, 1},
      {"|u1", false, 1, false, false, 2}, {"<u1", true, 1, false, false, 3},
      {"<i8", false, 8, false, false, 1}, {">i4", true, 4, false, true, 1},
      {"<f4", false, 4, true, false, 1},  {"<f8", true, 8, true, false, 1},
      {">f8", false, 8, true, true, 1}};
  for (const Case& k : cases) {
    SCOPED_TRACE(k.descr + (k.fortran ? " F" : " C"));
    const std::string path = file("g.npy", npy(k.descr, k.fortran, "(3, 4, 5)",
                                               make(k.fortran, k.bytes, k.is_float, k.big), k.version));
    const VoxelGrid g = read_voxels(path);
    ASSERT_EQ(g.nx(), s0);
    ASSERT_EQ(g.ny(), s1);
    ASSERT_EQ(g.nz(), s2);
    EXPECT_EQ(g.voxel_size(), 1.0);
    for (int i = 0; i < s0; ++i) {
      for (int j = 0; j < s1; ++j) {
        for (int kk = 0; kk < s2; ++kk) EXPECT_EQ(g.get(i, j, kk), pattern(i, j, kk)) << i << j << kk;
      }
    }
  }
}

TEST_F(MeshIoTest, BadNpy) {
  const std::string ok(24, '\1');
  expect_voxel_error(file("2d.npy", npy("|b1", false, "(4, 6)", ok)), "3-D");
  expect_voxel_error(file("4d.npy", npy("|b1", false, "(2, 2, 2, 3)", ok)), "3-D");
  expect_voxel_error(file("1d.npy", npy("|b1", false, "(24,)", ok)), "(24,)");
  expect_voxel_error(file("cut.npy", npy("|b1", false, "(2, 3, 5)", ok)), "truncated");
  expect_voxel_error(file("cut8.npy", npy("<f8", false, "(2, 3, 4)", ok)), "truncated");
  expect_voxel_error(file("long.npy", npy("|b1", false, "(2, 3, 3)", ok)), "more than");
  expect_voxel_error(file("empty.npy", npy("|b1", false, "(0, 3, 3)", "")), "empty");
  expect_voxel_error(file("cplx.npy", npy("<c16", false, "(1, 1, 1)", std::string(16, '\0'))), "not supported");
  expect_voxel_error(file("str.npy", npy("<U3", false, "(1, 1, 1)", std::string(12, '\0'))), "not supported");
  expect_voxel_error(file("obj.npy", npy("|O", false, "(1, 1, 1)", std::string(8, '\0'))), "not supported");
  std::string nan;
  put_double(nan, std::nan(""));
  expect_voxel_error(file("nan.npy", npy("<f8", false, "(1, 1, 1)", nan)), "NaN");
  expect_voxel_error(file("huge.npy", npy("|b1", false, "(100000, 100000, 100000)", ok)), "limit");
  expect_voxel_error(file("head.npy", std::string("\x93NUMPY\x01\0\xff\x7f{'descr'", 17)), "truncated");
  expect_voxel_error(file("v9.npy", std::string("\x93NUMPY\x09\0\x10\0{}              ", 26)), "version");
  expect_voxel_error(file("noshape.npy", npy("|b1", false, "(1, 1, 1)", "\1").replace(28, 7, "'shap':")),
                     "shape");
  expect_voxel_error(file("empty.binvox", ""), "empty");
  expect_voxel_error(file("text.npy", "hello"), "not a NumPy");
}

TEST_F(MeshIoTest, ReadsHandWrittenBinvox) {
  // 2 x 2 x 2, y fastest, then z, then x: index = x * 4 + z * 2 + y.
  // Solid: (x=1, y=0, z=0) -> 4, (x=0, y=1, z=0) -> 1, (x=0, y=0, z=1) -> 2, (1, 1, 1) -> 7.
  // Runs: 0 x1, 1 x2 (indices 1, 2), 0 x1, 1 x1 (4), 0 x2, 1 x1 (7).
  std::string s = "#binvox 1\ndim 2 2 2\ntranslate -1 2 0.5\nscale 3\ndata\n";
  for (int b : {0, 1, 1, 2, 0, 1, 1, 1, 0, 2, 1, 1}) s += static_cast<char>(b);
  const VoxelGrid g = read_voxels(file("hand.binvox", s));
  ASSERT_EQ(g.nx(), 2);
  EXPECT_EQ(g.count(), 4u);
  EXPECT_TRUE(g.get(1, 0, 0));
  EXPECT_TRUE(g.get(0, 1, 0));
  EXPECT_TRUE(g.get(0, 0, 1));
  EXPECT_TRUE(g.get(1, 1, 1));
  EXPECT_FALSE(g.get(0, 0, 0));
  EXPECT_FALSE(g.get(1, 1, 0));
  EXPECT_DOUBLE_EQ(g.origin_x(), -1);
  EXPECT_DOUBLE_EQ(g.origin_y(), 2);
  EXPECT_DOUBLE_EQ(g.origin_z(), 0.5);
  EXPECT_DOUBLE_EQ(g.voxel_size(), 1.5);

  // Non-cubic: "dim depth height width" = x, z, y extents: dim 3 1 2 is nx 3, nz 1, ny 2.
  std::string r = "#binvox 1\ndim 3 1 2\ndata\n";
  for (int b : {0, 3, 1, 1, 0, 2}) r += static_cast<char>(b);  // index 3 = x 1, z 0, y 1
  const VoxelGrid n = read_voxels(file("rect.binvox", r));
  EXPECT_EQ(n.nx(), 3);
  EXPECT_EQ(n.ny(), 2);
  EXPECT_EQ(n.nz(), 1);
  EXPECT_EQ(n.count(), 1u);
  EXPECT_TRUE(n.get(1, 1, 0));
}

TEST_F(MeshIoTest, BadBinvox) {
  const std::string head = "#binvox 1\ndim 2 2 2\ntranslate 0 0 0\nscale 1\ndata\n";
  expect_voxel_error(file("short.binvox", head + std::string("\0\x05", 2)), "truncated");
  expect_voxel_error(file("odd.binvox", head + std::string("\0\x05\x01", 3)), "truncated");
  expect_voxel_error(file("over.binvox", head + std::string("\0\x09", 2)), "past");
  expect_voxel_error(file("nodata.binvox", "#binvox 1\ndim 2 2 2\n"), "truncated");
  expect_voxel_error(file("nodim.binvox", "#binvox 1\nscale 1\ndata\n"), "no dim");
  expect_voxel_error(file("zerodim.binvox", "#binvox 1\ndim 0 2 2\ndata\n"), "dim");
  expect_voxel_error(file("scale.binvox", "#binvox 1\ndim 1 1 1\nscale nan\ndata\n\1\1"), "scale");
  expect_voxel_error(file("huge.binvox", "#binvox 1\ndim 100000 100000 100000\ndata\n"), "limit");
  expect_voxel_error(file("x.binvox", "solid x\n"), "not a binvox");
}

}  // namespace
}  // namespace csgfit
