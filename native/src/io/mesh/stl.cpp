// STL, binary and ASCII: which one is decided by the size a binary header implies, since
// binary headers are free text and often start with "solid" too.

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/mesh/mesh_builder.h"
#include "io/sniff.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

std::uint64_t declared_triangles(const std::string& d) { return le32(bytes_of(d) + 80); }

TriangleMesh read_stl_binary(const std::string& path, const std::string& d,
                             const MeshReadOptions& options, MeshReadInfo* info) {
  const unsigned char* bytes = bytes_of(d);
  const std::size_t n = le32(bytes + 80);
  MeshBuilder b(path, options);
  if (n > options.max_triangles) b.fail_too_many_triangles();
  b.reserve_triangles(n);
  b.reserve_vertices(std::min<std::size_t>(n, options.max_vertices));
  for (std::size_t t = 0; t < n; ++t) {
    const unsigned char* rec = bytes + 84 + 50 * t + 12;  // skip the normal
    long long idx[3];
    for (int v = 0; v < 3; ++v) {
      const unsigned char* q = rec + 12 * v;
      idx[v] =
          b.add_welded_vertex(load<float>(q, false), load<float>(q + 4, false),
                              load<float>(q + 8, false), "triangle", static_cast<long long>(t + 1));
    }
    b.add_face(idx, 3);
  }
  return b.finish("STL (binary)", info);
}

TriangleMesh read_stl_ascii(const std::string& path, const std::string& d,
                            const MeshReadOptions& options, MeshReadInfo* info) {
  Cursor c{d.data(), d.data() + d.size()};
  MeshBuilder b(path, options);
  // ASCII STL has ~250 bytes per facet: a cheap bound on what to reserve.
  b.reserve_triangles(std::min<std::size_t>(d.size() / 200, options.max_triangles));
  auto where = [&c] { return "line " + std::to_string(c.line); };
  auto bad = [&](const std::string& what) {
    if (c.at_end()) fail(quoted(path) + " is truncated (ends inside a facet, before " + what + ")");
    fail(quoted(path) + " " + where() + ": bad ASCII STL (expected " + what + ")");
  };
  auto expect = [&](const char* word) {
    if (!equals_ci(next_token(c), word)) bad("'" + std::string(word) + "'");
  };
  std::vector<long long> polygon;
  expect("solid");
  skip_line(c);  // the solid's name
  bool in_solid = true;
  for (;;) {
    const std::string_view t = next_token(c);
    if (t.empty()) break;
    if (in_solid && equals_ci(t, "facet")) {
      expect("normal");
      double ignored;
      for (int i = 0; i < 3; ++i) {
        if (!parse_double(next_token(c), &ignored)) bad("a facet normal component");
      }
      expect("outer");
      expect("loop");
      polygon.clear();
      for (;;) {
        const std::string_view v = next_token(c);
        if (equals_ci(v, "endloop")) break;
        if (!equals_ci(v, "vertex")) bad("'vertex' or 'endloop'");
        double xyz[3];
        for (double& x : xyz) {
          if (!parse_double(next_token(c), &x)) bad("a vertex coordinate");
        }
        if (polygon.size() > 1000) bad("'endloop'");
        polygon.push_back(b.add_welded_vertex(xyz[0], xyz[1], xyz[2], "line", c.line));
      }
      expect("endfacet");
      b.add_face(polygon.data(), polygon.size());
    } else if (in_solid && equals_ci(t, "endsolid")) {
      skip_line(c);
      in_solid = false;
    } else if (!in_solid && equals_ci(t, "solid")) {  // several solids in one file
      skip_line(c);
      in_solid = true;
    } else {
      bad(in_solid ? "'facet' or 'endsolid'" : "'solid' or the end of the file");
    }
  }
  if (in_solid) fail(quoted(path) + " is truncated (no 'endsolid' at the end)");
  return b.finish("STL (ASCII)", info);
}

// Neither binary nor ASCII STL: says what is wrong with the file.
[[noreturn]] void fail_not_stl(const std::string& path, const std::string& d,
                               const MeshReadOptions& options) {
  const std::string what = sniff(d);
  if (!what.empty() && what != "an ASCII STL mesh") fail_mislabelled(path, what, "an STL mesh");
  if (d.size() < 84) {
    fail(quoted(path) + " is not an STL mesh (too short for binary STL, and not ASCII STL)");
  }
  if (!has_binary_bytes(d)) {
    fail(quoted(path) + " is not an STL mesh (text that does not start with 'solid')");
  }
  const std::uint64_t n = declared_triangles(d);
  if (n > options.max_triangles) {
    fail(quoted(path) + " declares " + std::to_string(n) + " triangles, over the limit of " +
         std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
  }
  if (84 + 50 * n > d.size()) {
    fail(quoted(path) + " is truncated: its binary STL header declares " +
         count_text(n, "triangle") + " (" + std::to_string(84 + 50 * n) +
         " bytes) but the file has " + std::to_string(d.size()) + " bytes");
  }
  fail(quoted(path) + " is not a valid STL mesh: " + std::to_string(d.size() - (84 + 50 * n)) +
       " bytes follow the " + count_text(n, "triangle") + " its binary header declares");
}

}  // namespace

TriangleMesh read_stl(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  if (d.size() >= 84 && 84 + 50 * declared_triangles(d) == d.size()) {
    return read_stl_binary(path, d, options, info);
  }
  std::size_t i = 0;
  while (i < d.size() && std::isspace(static_cast<unsigned char>(d[i]))) ++i;
  const bool says_solid = starts_with_ci(d.data() + i, d.data() + d.size(), "solid");
  if (says_solid && !has_binary_bytes(d)) return read_stl_ascii(path, d, options, info);
  fail_not_stl(path, d, options);
}

}  // namespace csgfit::io_detail
