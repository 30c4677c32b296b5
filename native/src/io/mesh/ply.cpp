// PLY, ascii and binary: the header's elements are read in order, the vertex and face
// elements kept and every other one skipped (in O(1) when its rows have a fixed size).

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "io/byte_order.h"
#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/mesh/mesh_builder.h"
#include "io/mesh/ply_header.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

// Reads typed values from the binary body; every read is bounds-checked by the caller through
// has().
class PlyBinary {
 public:
  PlyBinary(const unsigned char* p, const unsigned char* end, bool big)
      : p_(p), end_(end), big_(big) {}
  bool has(std::size_t n) const { return static_cast<std::size_t>(end_ - p_) >= n; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  void skip(std::size_t n) { p_ += n; }
  double read(PlyType t) {
    const unsigned char* p = p_;
    p_ += ply_size(t);
    switch (t) {
      case PlyType::kInt8:
        return load<std::int8_t>(p, big_);
      case PlyType::kUint8:
        return load<std::uint8_t>(p, big_);
      case PlyType::kInt16:
        return load<std::int16_t>(p, big_);
      case PlyType::kUint16:
        return load<std::uint16_t>(p, big_);
      case PlyType::kInt32:
        return load<std::int32_t>(p, big_);
      case PlyType::kUint32:
        return load<std::uint32_t>(p, big_);
      case PlyType::kFloat32:
        return load<float>(p, big_);
      case PlyType::kFloat64:
        return load<double>(p, big_);
    }
    return 0;
  }

 private:
  const unsigned char* p_;
  const unsigned char* end_;
  bool big_;
};

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

// Reads the body row by row into the mesh builder. Bad faces are reported only once the whole
// body has been read (problem()): data shifted by a wrong count in the header looks like
// garbage faces, and "truncated" is the more useful message.
class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& path, const std::string& d, const PlyLayout& layout,
                MeshBuilder& b)
      : path_(path), d_(d), layout_(layout), b_(b) {}

  void read_ascii(const std::vector<PlyElement>& elements, std::size_t body);
  void read_binary(const std::vector<PlyElement>& elements, std::size_t body, bool big);
  const std::string& problem() const { return problem_; }

 private:
  [[noreturn]] void truncated(const PlyElement& e, unsigned long long got) const {
    fail(quoted(path_) + " is truncated: it declares " + std::to_string(e.count) + " " + e.name +
         " elements but the data ends after " + std::to_string(got));
  }
  void note(const std::string& what) {
    if (problem_.empty()) problem_ = quoted(path_) + ": " + what;
  }
  bool is_face_list(const PlyElement& e, std::size_t pi) const {
    return &e == layout_.face_el && static_cast<int>(pi) == layout_.iface;
  }
  long long to_index(double v);
  std::size_t list_count(double v, std::size_t item_size, std::size_t available) const;
  void begin_row(const PlyElement& e) {
    values_.assign(e.properties.size(), 0);
    face_.clear();
  }
  void end_row(const PlyElement& e, unsigned long long r);

  const std::string& path_;
  const std::string& d_;
  const PlyLayout& layout_;
  MeshBuilder& b_;
  std::vector<long long> face_;
  std::vector<double> values_;
  std::string problem_;
};

long long PlyBodyReader::to_index(double v) {
  if (!(v == std::floor(v)) || v < 0 || v >= static_cast<double>(INT_MAX)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    note(std::string("a face has vertex index ") + buf + " (face index out of range)");
    return -1;
  }
  return static_cast<long long>(v);
}

// A list's item count; SIZE_MAX when the items cannot fit in the `available` bytes, each
// taking at least item_size (ASCII: 2).
std::size_t PlyBodyReader::list_count(double v, std::size_t item_size,
                                      std::size_t available) const {
  if (!(v >= 0) || v != std::floor(v)) fail(quoted(path_) + ": a PLY list has a negative count");
  if (v > static_cast<double>(available / item_size)) return SIZE_MAX;
  return static_cast<std::size_t>(v);
}

void PlyBodyReader::end_row(const PlyElement& e, unsigned long long r) {
  if (&e == layout_.vertex_el) {
    b_.add_vertex(values_[layout_.ix], values_[layout_.iy], values_[layout_.iz], "vertex",
                  static_cast<long long>(r + 1));
  } else if (&e == layout_.face_el) {
    if (face_.size() < 3) {
      note("face " + std::to_string(r + 1) + " has fewer than 3 vertices");
    } else if (std::find(face_.begin(), face_.end(), -1) == face_.end()) {
      b_.add_face(face_.data(), face_.size());
    }
  }
}

void PlyBodyReader::read_ascii(const std::vector<PlyElement>& elements, std::size_t body) {
  Cursor a{d_.data() + std::min(body, d_.size()), d_.data() + d_.size()};
  for (const PlyElement& e : elements) {
    for (unsigned long long r = 0; r < e.count; ++r) {
      begin_row(e);
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        double v;
        std::string_view tok = next_token(a);
        if (tok.empty()) truncated(e, r);
        if (!parse_double(tok, &v)) {
          fail(quoted(path_) + " line " + std::to_string(a.line) + ": bad PLY value '" +
               std::string(tok.substr(0, 20)) + "'");
        }
        if (!e.properties[pi].is_list) {
          values_[pi] = v;
          continue;
        }
        const std::size_t n = list_count(v, 2, static_cast<std::size_t>(a.end - a.p));
        if (n == SIZE_MAX) truncated(e, r);
        for (std::size_t k = 0; k < n; ++k) {
          tok = next_token(a);
          if (tok.empty()) truncated(e, r);
          if (!parse_double(tok, &v)) {
            fail(quoted(path_) + " line " + std::to_string(a.line) + ": bad PLY list value");
          }
          if (is_face_list(e, pi)) face_.push_back(to_index(v));
        }
      }
      end_row(e, r);
    }
  }
}

void PlyBodyReader::read_binary(const std::vector<PlyElement>& elements, std::size_t body,
                                bool big) {
  const unsigned char* base = bytes_of(d_);
  PlyBinary in(base + std::min(body, d_.size()), base + d_.size(), big);
  for (const PlyElement& e : elements) {
    const bool wanted = &e == layout_.vertex_el || &e == layout_.face_el;
    std::size_t stride = 0;
    bool fixed = true;
    for (const PlyProperty& p : e.properties) {
      if (p.is_list) {
        fixed = false;
      } else {
        stride += ply_size(p.type);
      }
    }
    if (fixed && stride != 0 && e.count > in.remaining() / stride) {
      truncated(e, in.remaining() / stride);
    }
    if (!wanted && fixed) {  // skipped in O(1), and a huge count has failed above at once
      in.skip(static_cast<std::size_t>(e.count) * stride);
      continue;
    }
    for (unsigned long long r = 0; r < e.count; ++r) {
      begin_row(e);
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        if (!p.is_list) {
          if (!in.has(ply_size(p.type))) truncated(e, r);
          values_[pi] = in.read(p.type);
          continue;
        }
        if (!in.has(ply_size(p.count_type))) truncated(e, r);
        const std::size_t item = ply_size(p.type);
        const double declared = in.read(p.count_type);  // before remaining() is taken
        const std::size_t n = list_count(declared, item, in.remaining());
        if (n == SIZE_MAX) truncated(e, r);
        if (is_face_list(e, pi)) {
          for (std::size_t k = 0; k < n; ++k) face_.push_back(to_index(in.read(p.type)));
        } else {
          in.skip(n * item);
        }
      }
      end_row(e, r);
    }
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
  PlyBodyReader reader(path, d, layout, b);
  if (h.format == PlyFormat::kAscii) {
    reader.read_ascii(h.elements, h.body);
  } else {
    reader.read_binary(h.elements, h.body, h.format == PlyFormat::kBig);
  }
  if (!reader.problem().empty()) {
    fail(reader.problem() + " (truncated, or wrong element counts in the header?)");
  }
  const char* format_name = h.format == PlyFormat::kAscii    ? "PLY (ascii)"
                            : h.format == PlyFormat::kLittle ? "PLY (binary little-endian)"
                                                             : "PLY (binary big-endian)";
  return b.finish(format_name, info);
}

}  // namespace csgfit::io_detail
