// Wavefront OBJ: only "v" and "f" lines are geometry we use.

#include <string>
#include <vector>

#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/mesh/mesh_builder.h"
#include "io/sniff.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

// The 0-based vertex of one "f" token ("7", "7/1", "7//3", "-2/1/1") on line `line`.
long long face_vertex(const std::string& path, long long line, std::string_view t,
                      const MeshBuilder& b) {
  auto where = [line] { return "line " + std::to_string(line); };
  long long index;
  std::string_view rest;
  if (!parse_int_prefix(t, &index, &rest) || (!rest.empty() && rest.front() != '/') || index == 0) {
    fail(quoted(path) + " " + where() + ": bad face vertex '" + std::string(t) + "'");
  }
  if (index > 0) return index - 1;
  // Negative indices count back from the last vertex defined so far.
  index += static_cast<long long>(b.vertex_count());
  if (index < 0) {
    fail(quoted(path) + " " + where() + ": face index " + std::string(t) + " is out of range (" +
         count_text(b.vertex_count(), "vertex") + " so far)");
  }
  return index;
}

}  // namespace

TriangleMesh read_obj(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "an OBJ mesh");
    if (has_binary_bytes(d)) fail(quoted(path) + " contains binary data, not a text OBJ mesh");
  }
  Cursor c{d.data(), d.data() + d.size()};
  MeshBuilder b(path, options);
  std::vector<long long> face;
  while (!c.at_end()) {
    const long long line = c.line;
    auto where = [line] { return "line " + std::to_string(line); };
    while (c.p < c.end && is_blank(*c.p)) ++c.p;
    if (c.at_end()) break;
    if (*c.p == '\n' || *c.p == '#') {
      skip_line(c);
      continue;
    }
    const std::string_view key = next_token_on_line(c);
    if (key == "v") {
      double xyz[3];
      for (double& x : xyz) {
        if (!parse_double(next_token_on_line(c), &x)) {
          fail(quoted(path) + " " + where() + ": a vertex needs 3 numeric coordinates");
        }
      }
      b.add_vertex(xyz[0], xyz[1], xyz[2], "line", line);
    } else if (key == "f") {
      face.clear();
      for (std::string_view t = next_token_on_line(c); !t.empty(); t = next_token_on_line(c)) {
        const long long index = face_vertex(path, line, t, b);
        if (face.size() > 100000) {
          fail(quoted(path) + " " + where() + ": face with too many vertices");
        }
        face.push_back(index);
      }
      if (face.size() < 3) {
        fail(quoted(path) + " " + where() + ": a face needs at least 3 vertices");
      }
      b.add_face(face.data(), face.size());
    }
    // vt, vn, vp, g, o, s, usemtl, mtllib, l, p and the rest are not geometry we use.
    skip_line(c);
  }
  return b.finish("OBJ", info);
}

}  // namespace csgfit::io_detail
