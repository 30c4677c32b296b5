// PLY meshes, ascii and binary: the vertex and face elements kept, every other one skipped
// (io/mesh/ply_body.h).

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/mesh/mesh_builder.h"
#include "io/mesh/ply_body.h"
#include "io/mesh/ply_header.h"

namespace csgfit::io_detail {

namespace {

// The vertex and face elements, and which of their properties are x, y, z and the vertex
// index list.
struct PlyLayout {
  const PlyElement* vertex_el = nullptr;
  const PlyElement* face_el = nullptr;
  int ix = -1, iy = -1, iz = -1, iface = -1;
};

PlyLayout find_layout(const std::string& path, const std::vector<PlyElement>& elements,
                      const MeshReadOptions& options) {
  PlyLayout l;
  for (const PlyElement& e : elements) {
    if ((e.name == "vertex" && l.vertex_el) || (e.name == "face" && l.face_el)) {
      fail(quoted(path) + ": PLY header declares more than one " + e.name + " element");
    }
    if (e.name == "vertex") {
      l.vertex_el = &e;
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (p.is_list) continue;
        if (p.name == "x") l.ix = static_cast<int>(i);
        if (p.name == "y") l.iy = static_cast<int>(i);
        if (p.name == "z") l.iz = static_cast<int>(i);
      }
      if (l.ix < 0 || l.iy < 0 || l.iz < 0) {
        fail(quoted(path) + ": PLY vertex element has no x, y and z properties");
      }
      if (e.count > options.max_vertices) {
        fail(quoted(path) + " declares " + std::to_string(e.count) +
             " vertices, over the limit of " + std::to_string(options.max_vertices) +
             " (MeshReadOptions::max_vertices)");
      }
    } else if (e.name == "face") {
      l.face_el = &e;
      int lists = 0, any_list = -1;
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (!p.is_list) continue;
        ++lists;
        any_list = static_cast<int>(i);
        if (p.name == "vertex_indices" || p.name == "vertex_index") l.iface = static_cast<int>(i);
      }
      if (l.iface < 0 && lists == 1) l.iface = any_list;
      if (l.iface < 0) fail(quoted(path) + ": PLY face element has no vertex_indices list");
      if (e.count > options.max_triangles) {
        fail(quoted(path) + " declares " + std::to_string(e.count) + " faces, over the limit of " +
             std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
      }
    }
  }
  if (l.vertex_el == nullptr) fail(quoted(path) + " has no vertex element");
  if (l.face_el == nullptr) {
    fail(quoted(path) + " has no triangles (no face element: a point cloud?)");
  }
  return l;
}

// Hands the vertex and face rows to the mesh builder. Bad faces are reported only once the
// whole body has been read (problem()): data shifted by a wrong count in the header looks like
// garbage faces, and "truncated" is the more useful message.
class PlyMeshRows : public PlyRowVisitor {
 public:
  PlyMeshRows(const PlyLayout& layout, MeshBuilder& b) : layout_(layout), b_(b) {}

  bool wanted(const PlyElement& e) const override {
    return &e == layout_.vertex_el || &e == layout_.face_el;
  }
  bool keeps_list(const PlyElement& e, std::size_t pi) const override {
    return &e == layout_.face_el && static_cast<int>(pi) == layout_.iface;
  }
  void row(const PlyElement& e, unsigned long long r, const std::vector<double>& values,
           const std::vector<double>& list) override;
  const std::string& problem() const { return problem_; }

 private:
  void note(const std::string& what) {
    if (problem_.empty()) problem_ = what;
  }
  long long to_index(double v);

  const PlyLayout& layout_;
  MeshBuilder& b_;
  std::vector<long long> face_;
  std::string problem_;
};

long long PlyMeshRows::to_index(double v) {
  if (!(v == std::floor(v)) || v < 0 || v >= static_cast<double>(INT_MAX)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    note(std::string("a face has vertex index ") + buf + " (face index out of range)");
    return -1;
  }
  return static_cast<long long>(v);
}

void PlyMeshRows::row(const PlyElement& e, unsigned long long r,
                      const std::vector<double>& values, const std::vector<double>& list) {
  if (&e == layout_.vertex_el) {
    b_.add_vertex(values[layout_.ix], values[layout_.iy], values[layout_.iz], "vertex",
                  static_cast<long long>(r + 1));
    return;
  }
  face_.clear();
  for (double v : list) face_.push_back(to_index(v));
  if (face_.size() < 3) {
    note("face " + std::to_string(r + 1) + " has fewer than 3 vertices");
  } else if (std::find(face_.begin(), face_.end(), -1) == face_.end()) {
    b_.add_face(face_.data(), face_.size());
  }
}

}  // namespace

TriangleMesh read_ply(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  const PlyHeader h = read_ply_header(path, d);
  const PlyLayout layout = find_layout(path, h.elements, options);
  MeshBuilder b(path, options);
  const std::size_t body_bytes = d.size() - std::min(h.body, d.size());
  b.reserve_vertices(std::min<std::size_t>(layout.vertex_el->count, body_bytes / 3));
  b.reserve_triangles(std::min<std::size_t>(layout.face_el->count, body_bytes / 4));
  PlyMeshRows rows(layout, b);
  read_ply_rows(path, d, h, rows);
  if (!rows.problem().empty()) {
    fail(quoted(path) + ": " + rows.problem() +
         " (truncated, or wrong element counts in the header?)");
  }
  const char* format_name = h.format == PlyFormat::kAscii    ? "PLY (ascii)"
                            : h.format == PlyFormat::kLittle ? "PLY (binary little-endian)"
                                                             : "PLY (binary big-endian)";
  return b.finish(format_name, info);
}

}  // namespace csgfit::io_detail
