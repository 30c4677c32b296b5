// Text OFF. Data is read a line at a time: extra values on a line are colours, normals or
// texture coordinates and are skipped; '#' starts a comment anywhere.

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "io/input_file.h"
#include "io/mesh/formats.h"
#include "io/mesh/mesh_builder.h"
#include "io/sniff.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

class LineReader {
 public:
  explicit LineReader(const std::string& d) : c_{d.data(), d.data() + d.size()} {}

  // Next line with content (comments removed); false at the end of the file.
  bool next(std::string_view* line) {
    while (!c_.at_end()) {
      line_no_ = c_.line;
      std::string_view l = take_line(c_);
      const std::size_t hash = l.find('#');
      if (hash != std::string_view::npos) l = l.substr(0, hash);
      std::size_t i = 0;
      while (i < l.size() && (is_blank(l[i]) || l[i] == '\n')) ++i;
      if (i < l.size()) {
        *line = l.substr(i);
        return true;
      }
    }
    return false;
  }
  long long line_number() const { return line_no_; }
  // Whether another line with content follows.
  bool more() const {
    LineReader copy = *this;
    std::string_view l;
    return copy.next(&l);
  }

 private:
  Cursor c_;
  long long line_no_ = 0;
};

// One file's reading state: the lines, the mesh, and the messages naming the current line.
struct OffReader {
  OffReader(const std::string& file, const std::string& data, const MeshReadOptions& limits)
      : path(file), d(data), options(limits), lines(data), b(file, limits) {}

  const std::string& path;
  const std::string& d;
  const MeshReadOptions& options;
  LineReader lines;
  std::string_view line;
  MeshBuilder b;

  std::string where() const { return "line " + std::to_string(lines.line_number()); }
  [[noreturn]] void bad(const std::string& what) const {
    fail(quoted(path) + " " + where() + ": " + what);
  }

  // Reads the header; returns the declared vertex and face counts.
  void read_header(unsigned long long* nv, unsigned long long* nf);
  void check_magic(std::string_view magic) const;
  void read_vertices(unsigned long long nv);
  void read_faces(unsigned long long nv, unsigned long long nf);
};

void OffReader::check_magic(std::string_view magic) const {
  std::size_t k = 0;
  while (k < magic.size() && std::strchr("STCN4n", magic[k]) != nullptr) ++k;
  if (magic.substr(k) != "OFF") {
    const std::string what = sniff(d);
    if (!what.empty() && what != "an OFF mesh") fail_mislabelled(path, what, "an OFF mesh");
    if (has_binary_bytes(d, 4096)) fail(quoted(path) + " contains binary data, not an OFF mesh");
    fail(quoted(path) + " is not an OFF mesh (it does not start with 'OFF')");
  }
  if (magic.find_first_of("4n") != std::string_view::npos) {
    fail(quoted(path) + ": " + std::string(magic) + " (4-D or n-D OFF) is not supported");
  }
}

void OffReader::read_header(unsigned long long* nv, unsigned long long* nf) {
  if (!lines.next(&line)) fail(quoted(path) + " has no OFF header (only comments or blank lines)");
  check_magic(take_token(&line));
  std::string_view t = take_token(&line);
  if (t == "BINARY") fail(quoted(path) + ": binary OFF is not supported (save it as text OFF)");
  if (t.empty()) {
    if (!lines.next(&line)) fail(quoted(path) + " is truncated (no vertex and face counts)");
    t = take_token(&line);
  }
  if (!parse_count(t, nv) || !parse_count(take_token(&line), nf)) {
    bad("bad OFF header (expected vertex and face counts)");
  }
  if (*nv > options.max_vertices) {
    fail(quoted(path) + " declares " + std::to_string(*nv) + " vertices, over the limit of " +
         std::to_string(options.max_vertices) + " (MeshReadOptions::max_vertices)");
  }
  if (*nf > options.max_triangles) {
    fail(quoted(path) + " declares " + std::to_string(*nf) + " faces, over the limit of " +
         std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
  }
}

void OffReader::read_vertices(unsigned long long nv) {
  for (unsigned long long v = 0; v < nv; ++v) {
    if (!lines.next(&line)) {
      fail(quoted(path) + " is truncated: it declares " + count_text(nv, "vertex") + " but has " +
           std::to_string(v));
    }
    double xyz[3];
    for (double& x : xyz) {
      if (!parse_double(take_token(&line), &x)) bad("a vertex needs 3 numeric coordinates");
    }
    b.add_vertex(xyz[0], xyz[1], xyz[2], "line", lines.line_number());
  }
}

void OffReader::read_faces(unsigned long long nv, unsigned long long nf) {
  std::vector<long long> face;
  for (unsigned long long f = 0; f < nf; ++f) {
    if (!lines.next(&line)) {
      fail(quoted(path) + " is truncated: it declares " + count_text(nf, "face") + " but has " +
           std::to_string(f));
    }
    unsigned long long n = 0;
    if (!parse_count(take_token(&line), &n)) bad("a face must start with its vertex count");
    if (n > nv || n > 100000) bad("a face with " + std::to_string(n) + " vertices");
    face.clear();
    for (unsigned long long k = 0; k < n; ++k) {
      unsigned long long index;
      const std::string_view it = take_token(&line);
      if (it.empty()) {
        if (!lines.more()) fail(quoted(path) + " is truncated (its last face is cut short)");
        bad("a face lists fewer indices than its count");
      }
      if (!parse_count(it, &index)) bad("bad face index '" + std::string(it) + "'");
      if (index >= nv) {
        bad("face index " + std::to_string(index) + " is out of range (" +
            count_text(nv, "vertex") + ", 0-based)");
      }
      face.push_back(static_cast<long long>(index));
    }
    if (n < 3) bad("a face needs at least 3 vertices");
    b.add_face(face.data(), face.size());
  }
}

}  // namespace

TriangleMesh read_off(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  OffReader r(path, d, options);
  unsigned long long nv = 0, nf = 0;
  r.read_header(&nv, &nf);
  // Each vertex line takes at least 6 bytes, each face line 7: no point reserving more.
  r.b.reserve_vertices(std::min<std::size_t>(nv, d.size() / 6));
  r.b.reserve_triangles(std::min<std::size_t>(nf, d.size() / 7));
  r.read_vertices(nv);
  r.read_faces(nv, nf);
  return r.b.finish("OFF", info);
}

}  // namespace csgfit::io_detail
