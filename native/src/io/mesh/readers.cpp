// Mesh (STL, OBJ, OFF, PLY) and voxel grid (.npy, .binvox) readers.
//
// Every reader works on the whole file in memory, checks each declared count against the
// limits before it allocates anything for it, and checks that the bytes the header promises
// are there before it reads them, so that a hostile header fails at once with one line.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"

namespace csgfit {

namespace {

// ---------------------------------------------------------------------------------------------
// Files and messages

std::string quoted(const std::string& path) { return "'" + path + "'"; }

[[noreturn]] void fail(const std::string& message) { throw InputError(message); }

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// The whole file. A std::string keeps a NUL after the last byte, which the number parsers
// below never rely on but which makes a stray strtod-style overrun impossible.
std::string read_whole_file(const std::string& path, long long max_bytes) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) fail("cannot open " + quoted(path) + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) fail("cannot open " + quoted(path) + ": " + std::strerror(EISDIR));
  if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    fail("cannot open " + quoted(path) + ": not a regular file");
  }
  const std::string too_big =
      quoted(path) + " is larger than " + std::to_string(max_bytes) + " bytes, the input limit";
  if (S_ISREG(st.st_mode) && st.st_size > max_bytes) fail(too_big);
  std::string data;
  if (S_ISREG(st.st_mode)) data.reserve(static_cast<std::size_t>(st.st_size));
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd.get(), chunk, sizeof chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("cannot read " + quoted(path) + ": " + std::strerror(errno));
    }
    if (n == 0) break;
    if (static_cast<long long>(data.size()) + n > max_bytes) fail(too_big);
    data.append(chunk, static_cast<std::size_t>(n));
  }
  if (data.empty()) fail(quoted(path) + " is empty (0 bytes)");
  return data;
}

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool starts_with(const std::string& d, const char* prefix) {
  return d.compare(0, std::strlen(prefix), prefix) == 0;
}

bool starts_with_ci(const char* p, const char* end, const char* word) {
  for (; *word; ++word, ++p) {
    if (p >= end || std::tolower(static_cast<unsigned char>(*p)) != *word) return false;
  }
  return true;
}

bool has_binary_bytes(const std::string& d, std::size_t limit = std::string::npos) {
  const std::size_t n = std::min(d.size(), limit);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(d[i]);
    if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v')) {
      return true;
    }
  }
  return false;
}

// What the content looks like, from signatures that do not occur at the start of the format
// named by the extension; empty when nothing is recognised.
std::string sniff(const std::string& d) {
  if (starts_with(d, "\x89PNG")) return "a PNG image";
  if (d.size() >= 3 && static_cast<unsigned char>(d[0]) == 0xFF &&
      static_cast<unsigned char>(d[1]) == 0xD8 && static_cast<unsigned char>(d[2]) == 0xFF) {
    return "a JPEG image";
  }
  if (starts_with(d, "GIF8")) return "a GIF image";
  if (starts_with(d, "%PDF")) return "a PDF document";
  if (starts_with(d, "PK\x03\x04")) return "a ZIP archive (3MF or a compressed mesh?)";
  if (d.size() >= 2 && static_cast<unsigned char>(d[0]) == 0x1F &&
      static_cast<unsigned char>(d[1]) == 0x8B) {
    return "gzip-compressed data";
  }
  if (starts_with(d, "\x93NUMPY")) return "a NumPy array (.npy)";
  if (starts_with(d, "#binvox")) return "a binvox voxel grid";
  if (starts_with(d, "ply\n") || starts_with(d, "ply\r")) return "a PLY mesh";
  if (starts_with(d, "glTF")) return "a binary glTF (.glb)";
  if (starts_with(d, "ISO-10303-21")) return "a STEP file";
  if (starts_with(d, "<?xml")) return "an XML document";
  {
    std::size_t i = 0;
    while (i < d.size() && std::isspace(static_cast<unsigned char>(d[i]))) ++i;
    const char* p = d.data() + i;
    const char* end = d.data() + d.size();
    if (starts_with_ci(p, end, "solid") && !has_binary_bytes(d, 4096) &&
        d.find("facet", i) != std::string::npos) {
      return "an ASCII STL mesh";
    }
    // OFF headers may carry prefixes (COFF, NOFF, STOFF...).
    std::size_t j = i;
    while (j < d.size() && j < i + 6 && std::strchr("STCN4n", d[j]) != nullptr && d[j] != 0) ++j;
    if (d.compare(j, 3, "OFF") == 0 &&
        (j + 3 == d.size() || std::isspace(static_cast<unsigned char>(d[j + 3])))) {
      return "an OFF mesh";
    }
  }
  return "";
}

[[noreturn]] void fail_mislabelled(const std::string& path, const std::string& what,
                                   const std::string& expected) {
  fail(quoted(path) + " looks like " + what + ", not " + expected + " (wrong file extension?)");
}

std::string count_text(std::size_t n, const char* noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// ---------------------------------------------------------------------------------------------
// Text scanning

struct Cursor {
  const char* p;
  const char* end;
  long long line = 1;

  bool at_end() const { return p >= end; }
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Skips spaces and newlines (counting lines).
void skip_space(Cursor& c) {
  while (c.p < c.end && (is_blank(*c.p) || *c.p == '\n')) {
    if (*c.p == '\n') ++c.line;
    ++c.p;
  }
}

// Next whitespace-delimited token (may be empty at the end).
std::string_view next_token(Cursor& c) {
  skip_space(c);
  const char* b = c.p;
  while (c.p < c.end && !is_blank(*c.p) && *c.p != '\n') ++c.p;
  return std::string_view(b, static_cast<std::size_t>(c.p - b));
}

void skip_line(Cursor& c) {
  while (c.p < c.end && *c.p != '\n') ++c.p;
  if (c.p < c.end) {
    ++c.p;
    ++c.line;
  }
}

bool equals_ci(std::string_view a, const char* b) {
  if (a.size() != std::strlen(b)) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  }
  return true;
}

// A decimal floating-point number (locale-independent); "nan"/"inf" parse and are refused by
// the caller with a message about non-finite coordinates.
bool parse_double(std::string_view t, double* value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// A signed integer prefix of t (e.g. the "12" of "12/4/7"); rest receives what follows.
bool parse_int_prefix(std::string_view t, long long* value, std::string_view* rest) {
  const char* b = t.data();
  const char* e = t.data() + t.size();
  if (b < e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, *value);
  if (r.ec != std::errc()) return false;
  *rest = std::string_view(r.ptr, static_cast<std::size_t>(e - r.ptr));
  return true;
}

// ---------------------------------------------------------------------------------------------
// Mesh assembly shared by the formats

// Collects polygons, checks them, triangulates and drops degenerate triangles.
class MeshBuilder {
 public:
  MeshBuilder(const std::string& path, const MeshReadOptions& options)
      : path_(path), options_(options) {}

  void reserve_vertices(std::size_t n) { mesh_.vertices.reserve(n); }
  void reserve_triangles(std::size_t n) { mesh_.triangles.reserve(n); }

  std::size_t vertex_count() const { return mesh_.vertices.size(); }

  // `what number` says where in the file (e.g. "line 12"); only formatted on failure.
  void add_vertex(double x, double y, double z, const char* what, long long number) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      fail(quoted(path_) + " " + what + " " + std::to_string(number) + ": vertex " +
           std::to_string(mesh_.vertices.size() + 1) + " has a non-finite coordinate (NaN or infinity)");
    }
    if (mesh_.vertices.size() >= options_.max_vertices) {
      fail(quoted(path_) + " has more than " + std::to_string(options_.max_vertices) +
           " vertices, over the limit");
    }
    mesh_.vertices.push_back({x, y, z});
  }

  // A welded vertex (STL has none shared): equal positions get one index.
  int add_welded_vertex(double x, double y, double z, const char* what, long long number) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      fail(quoted(path_) + " " + what + " " + std::to_string(number) +
           ": a vertex has a non-finite coordinate (NaN or infinity)");
    }
    Key key{x + 0.0, y + 0.0, z + 0.0};  // -0 and +0 are one position
    const auto it = weld_.find(key);
    if (it != weld_.end()) return it->second;
    add_vertex(key.x, key.y, key.z, what, number);
    const int index = static_cast<int>(mesh_.vertices.size() - 1);
    weld_.emplace(key, index);
    return index;
  }

  // A face given by 0-based vertex indices, checked against the vertex count later (OBJ and
  // PLY may list faces before all vertices).
  void add_face(const long long* indices, std::size_t n) {
    ++faces_;
    if (n < 3) fail(quoted(path_) + ": face " + std::to_string(faces_) + " has fewer than 3 vertices");
    if (mesh_.triangles.size() + (n - 2) > options_.max_triangles) fail_too_many_triangles();
    for (std::size_t i = 0; i < n; ++i) {
      if (indices[i] < 0 || indices[i] >= INT_MAX) fail_index(indices[i]);
    }
    for (std::size_t i = 1; i + 1 < n; ++i) {
      mesh_.triangles.push_back({static_cast<int>(indices[0]), static_cast<int>(indices[i]),
                                 static_cast<int>(indices[i + 1])});
    }
  }

  [[noreturn]] void fail_too_many_triangles() const {
    fail(quoted(path_) + " has more than " + std::to_string(options_.max_triangles) +
         " triangles, over the limit (MeshReadOptions::max_triangles)");
  }

  [[noreturn]] void fail_index(long long index) const {
    fail(quoted(path_) + ": face " + std::to_string(faces_) + " refers to vertex " +
         std::to_string(index + 1) + " (1-based) but there are " +
         count_text(mesh_.vertices.size(), "vertex") + " (face index out of range)");
  }

  TriangleMesh finish(const std::string& format, MeshReadInfo* info) {
    const std::size_t nv = mesh_.vertices.size();
    std::size_t kept = 0;
    std::size_t dropped = 0;
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      const auto& tri = mesh_.triangles[t];
      for (int v : tri) {
        if (static_cast<std::size_t>(v) >= nv) {
          fail(quoted(path_) + ": a face refers to vertex " + std::to_string(v + 1) +
               " (1-based) but there are " + count_text(nv, "vertex") +
               " (face index out of range)");
        }
      }
      if (degenerate(tri)) {
        ++dropped;
        continue;
      }
      mesh_.triangles[kept++] = tri;
    }
    mesh_.triangles.resize(kept);
    if (kept == 0) {
      fail(quoted(path_) + " has no triangles" +
           (dropped ? " (all " + std::to_string(dropped) + " are degenerate)" : std::string()));
    }
    mesh_.triangles.shrink_to_fit();
    if (info) {
      info->format = format;
      info->faces_read = faces_;
      info->degenerate_dropped = dropped;
    }
    return std::move(mesh_);
  }

  void count_face() { ++faces_; }

 private:
  struct Key {
    double x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ULL;
      for (double v : {k.x, k.y, k.z}) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        h = (h ^ bits) * 1099511628211ULL;
        h ^= h >> 29;
      }
      return static_cast<std::size_t>(h);
    }
  };

  // Zero area up to rounding: repeated vertices or (nearly exactly) collinear ones.
  bool degenerate(const std::array<int, 3>& t) const {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
    const auto& a = mesh_.vertices[t[0]];
    const auto& b = mesh_.vertices[t[1]];
    const auto& c = mesh_.vertices[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                         u[0] * v[1] - u[1] * v[0]};
    const double n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    const double e2 = std::max(u[0] * u[0] + u[1] * u[1] + u[2] * u[2],
                               v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return n2 <= 1e-24 * e2 * e2;
  }

  const std::string& path_;
  const MeshReadOptions& options_;
  TriangleMesh mesh_;
  std::size_t faces_ = 0;
  std::unordered_map<Key, int, KeyHash> weld_;
};

// ---------------------------------------------------------------------------------------------
// STL

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

float le_float(const unsigned char* p) {
  const std::uint32_t bits = le32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

TriangleMesh read_stl_binary(const std::string& path, const std::string& d,
                             const MeshReadOptions& options, MeshReadInfo* info) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(d.data());
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
      idx[v] = b.add_welded_vertex(le_float(q), le_float(q + 4), le_float(q + 8), "triangle",
                                   static_cast<long long>(t + 1));
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

TriangleMesh read_stl(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  // Binary STL headers are free text and often start with "solid" too: the size check decides.
  if (d.size() >= 84) {
    const std::uint64_t n = le32(reinterpret_cast<const unsigned char*>(d.data()) + 80);
    if (84 + 50 * n == d.size()) return read_stl_binary(path, d, options, info);
  }
  std::size_t i = 0;
  while (i < d.size() && std::isspace(static_cast<unsigned char>(d[i]))) ++i;
  const bool says_solid = starts_with_ci(d.data() + i, d.data() + d.size(), "solid");
  if (says_solid && !has_binary_bytes(d)) return read_stl_ascii(path, d, options, info);
  const std::string what = sniff(d);
  if (!what.empty() && what != "an ASCII STL mesh") fail_mislabelled(path, what, "an STL mesh");
  if (d.size() < 84) {
    fail(quoted(path) + " is not an STL mesh (too short for binary STL, and not ASCII STL)");
  }
  if (!has_binary_bytes(d)) {
    fail(quoted(path) + " is not an STL mesh (text that does not start with 'solid')");
  }
  const std::uint64_t n = le32(reinterpret_cast<const unsigned char*>(d.data()) + 80);
  if (n > options.max_triangles) {
    fail(quoted(path) + " declares " + std::to_string(n) + " triangles, over the limit of " +
         std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
  }
  if (84 + 50 * n > d.size()) {
    fail(quoted(path) + " is truncated: its binary STL header declares " + count_text(n, "triangle") +
         " (" + std::to_string(84 + 50 * n) + " bytes) but the file has " +
         std::to_string(d.size()) + " bytes");
  }
  fail(quoted(path) + " is not a valid STL mesh: " + std::to_string(d.size() - (84 + 50 * n)) +
       " bytes follow the " + count_text(n, "triangle") + " its binary header declares");
}

// ---------------------------------------------------------------------------------------------
// OBJ

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
    const char* kb = c.p;
    while (c.p < c.end && !is_blank(*c.p) && *c.p != '\n') ++c.p;
    const std::string_view key(kb, static_cast<std::size_t>(c.p - kb));
    auto token = [&c]() -> std::string_view {
      while (c.p < c.end && is_blank(*c.p)) ++c.p;
      const char* tb = c.p;
      while (c.p < c.end && !is_blank(*c.p) && *c.p != '\n') ++c.p;
      return std::string_view(tb, static_cast<std::size_t>(c.p - tb));
    };
    if (key == "v") {
      double xyz[3];
      for (double& x : xyz) {
        const std::string_view t = token();
        if (!parse_double(t, &x)) {
          fail(quoted(path) + " " + where() + ": a vertex needs 3 numeric coordinates");
        }
      }
      b.add_vertex(xyz[0], xyz[1], xyz[2], "line", line);
    } else if (key == "f") {
      face.clear();
      for (;;) {
        const std::string_view t = token();
        if (t.empty()) break;
        long long index;
        std::string_view rest;
        if (!parse_int_prefix(t, &index, &rest) || (!rest.empty() && rest.front() != '/') ||
            index == 0) {
          fail(quoted(path) + " " + where() + ": bad face vertex '" + std::string(t) + "'");
        }
        // Negative indices count back from the last vertex defined so far.
        if (index < 0) {
          index += static_cast<long long>(b.vertex_count());
          if (index < 0) {
            fail(quoted(path) + " " + where() + ": face index " + std::string(t) +
                 " is out of range (" + count_text(b.vertex_count(), "vertex") + " so far)");
          }
        } else {
          index -= 1;
        }
        if (face.size() > 100000) fail(quoted(path) + " " + where() + ": face with too many vertices");
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

// ---------------------------------------------------------------------------------------------
// OFF

// OFF data is read a line at a time (extra values on a line are colours, normals or texture
// coordinates and are skipped); '#' starts a comment anywhere.
class LineReader {
 public:
  explicit LineReader(const std::string& d) : c_{d.data(), d.data() + d.size()} {}

  // Next line with content (comments removed); false at the end of the file.
  bool next(std::string_view* line) {
    while (!c_.at_end()) {
      line_no_ = c_.line;
      const char* b = c_.p;
      skip_line(c_);
      const char* e = c_.p;
      std::string_view l(b, static_cast<std::size_t>(e - b));
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

std::string_view take_token(std::string_view* s) {
  std::size_t i = 0;
  while (i < s->size() && (is_blank((*s)[i]) || (*s)[i] == '\n')) ++i;
  std::size_t j = i;
  while (j < s->size() && !is_blank((*s)[j]) && (*s)[j] != '\n') ++j;
  const std::string_view t = s->substr(i, j - i);
  s->remove_prefix(j);
  return t;
}

bool parse_count(std::string_view t, unsigned long long* value) {
  if (t.empty() || t.front() == '-') return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

TriangleMesh read_off(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  LineReader lines(d);
  std::string_view line;
  auto where = [&lines] { return "line " + std::to_string(lines.line_number()); };
  if (!lines.next(&line)) fail(quoted(path) + " has no OFF header (only comments or blank lines)");
  std::string_view magic = take_token(&line);
  {
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
  std::string_view t = take_token(&line);
  if (t == "BINARY") fail(quoted(path) + ": binary OFF is not supported (save it as text OFF)");
  if (t.empty()) {
    if (!lines.next(&line)) fail(quoted(path) + " is truncated (no vertex and face counts)");
    t = take_token(&line);
  }
  unsigned long long nv = 0, nf = 0;
  if (!parse_count(t, &nv) || !parse_count(take_token(&line), &nf)) {
    fail(quoted(path) + " " + where() + ": bad OFF header (expected vertex and face counts)");
  }
  MeshBuilder b(path, options);
  if (nv > options.max_vertices) {
    fail(quoted(path) + " declares " + std::to_string(nv) + " vertices, over the limit of " +
         std::to_string(options.max_vertices) + " (MeshReadOptions::max_vertices)");
  }
  if (nf > options.max_triangles) {
    fail(quoted(path) + " declares " + std::to_string(nf) + " faces, over the limit of " +
         std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
  }
  // Each vertex line takes at least 6 bytes, each face line 7: no point reserving more.
  b.reserve_vertices(std::min<std::size_t>(nv, d.size() / 6));
  b.reserve_triangles(std::min<std::size_t>(nf, d.size() / 7));
  for (unsigned long long v = 0; v < nv; ++v) {
    if (!lines.next(&line)) {
      fail(quoted(path) + " is truncated: it declares " + count_text(nv, "vertex") + " but has " +
           std::to_string(v));
    }
    double xyz[3];
    for (double& x : xyz) {
      if (!parse_double(take_token(&line), &x)) {
        fail(quoted(path) + " " + where() + ": a vertex needs 3 numeric coordinates");
      }
    }
    b.add_vertex(xyz[0], xyz[1], xyz[2], "line", lines.line_number());
  }
  std::vector<long long> face;
  for (unsigned long long f = 0; f < nf; ++f) {
    if (!lines.next(&line)) {
      fail(quoted(path) + " is truncated: it declares " + count_text(nf, "face") + " but has " +
           std::to_string(f));
    }
    unsigned long long n = 0;
    if (!parse_count(take_token(&line), &n)) {
      fail(quoted(path) + " " + where() + ": a face must start with its vertex count");
    }
    if (n > nv || n > 100000) {
      fail(quoted(path) + " " + where() + ": a face with " + std::to_string(n) + " vertices");
    }
    face.clear();
    for (unsigned long long k = 0; k < n; ++k) {
      unsigned long long index;
      const std::string_view it = take_token(&line);
      if (it.empty()) {
        if (!lines.more()) fail(quoted(path) + " is truncated (its last face is cut short)");
        fail(quoted(path) + " " + where() + ": a face lists fewer indices than its count");
      }
      if (!parse_count(it, &index)) fail(quoted(path) + " " + where() + ": bad face index '" + std::string(it) + "'");
      if (index >= nv) {
        fail(quoted(path) + " " + where() + ": face index " + std::to_string(index) +
             " is out of range (" + count_text(nv, "vertex") + ", 0-based)");
      }
      face.push_back(static_cast<long long>(index));
    }
    if (n < 3) fail(quoted(path) + " " + where() + ": a face needs at least 3 vertices");
    b.add_face(face.data(), face.size());
  }
  return b.finish("OFF", info);
}

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool ply_type(std::string_view name, PlyType* t) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, type] : kTypes) {
    if (name == n) {
      *t = type;
      return true;
    }
  }
  return false;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8: return 1;
    case PlyType::kInt16:
    case PlyType::kUint16: return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
  PlyType type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kLittle, kBig };

// Reads typed values from the binary body; every read is bounds-checked by the caller through
// has().
class PlyBinary {
 public:
  PlyBinary(const unsigned char* p, const unsigned char* end, bool big) : p_(p), end_(end), big_(big) {}
  bool has(std::size_t n) const { return static_cast<std::size_t>(end_ - p_) >= n; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  void skip(std::size_t n) { p_ += n; }
  double read(PlyType t) {
    unsigned char b[8];
    const std::size_t n = ply_size(t);
    for (std::size_t i = 0; i < n; ++i) b[i] = big_ ? p_[n - 1 - i] : p_[i];
    p_ += n;
    switch (t) {
      case PlyType::kInt8: return static_cast<std::int8_t>(b[0]);
      case PlyType::kUint8: return b[0];
      case PlyType::kInt16: {
        std::int16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case PlyType::kUint16: {
        std::uint16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case PlyType::kInt32: {
        std::int32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::kUint32: {
        std::uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::kFloat32: {
        float v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case PlyType::kFloat64: {
        double v;
        std::memcpy(&v, b, 8);
        return v;
      }
    }
    return 0;
  }

 private:
  const unsigned char* p_;
  const unsigned char* end_;
  bool big_;
};

TriangleMesh read_ply(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info) {
  if (!(starts_with(d, "ply\n") || starts_with(d, "ply\r"))) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a PLY mesh");
    fail(quoted(path) + " is not a PLY mesh (it does not start with 'ply')");
  }
  const std::size_t header_end = d.find("end_header");
  if (header_end == std::string::npos) fail(quoted(path) + " is truncated (no 'end_header' line)");
  Cursor c{d.data(), d.data() + header_end};
  skip_line(c);  // "ply"
  PlyFormat format = PlyFormat::kAscii;
  bool have_format = false;
  std::vector<PlyElement> elements;
  auto bad_header = [&](const std::string& what) {
    fail(quoted(path) + " line " + std::to_string(c.line) + ": bad PLY header (" + what + ")");
  };
  while (!c.at_end()) {
    const char* lb = c.p;
    skip_line(c);
    std::string_view line(lb, static_cast<std::size_t>(c.p - lb));
    const std::string_view key = take_token(&line);
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      const std::string_view f = take_token(&line);
      if (f == "ascii") format = PlyFormat::kAscii;
      else if (f == "binary_little_endian") format = PlyFormat::kLittle;
      else if (f == "binary_big_endian") format = PlyFormat::kBig;
      else bad_header("unknown format '" + std::string(f) + "'");
      have_format = true;
    } else if (key == "element") {
      PlyElement e;
      e.name = std::string(take_token(&line));
      if (e.name.empty() || !parse_count(take_token(&line), &e.count)) bad_header("element needs a name and a count");
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) bad_header("property before any element");
      PlyProperty p;
      std::string_view t = take_token(&line);
      if (t == "list") {
        p.is_list = true;
        if (!ply_type(take_token(&line), &p.count_type)) bad_header("unknown list count type");
        if (p.count_type == PlyType::kFloat32 || p.count_type == PlyType::kFloat64) {
          bad_header("a list count must be an integer type");
        }
        t = take_token(&line);
      }
      if (!ply_type(t, &p.type)) bad_header("unknown property type '" + std::string(t) + "'");
      p.name = std::string(take_token(&line));
      if (p.name.empty()) bad_header("property without a name");
      elements.back().properties.push_back(std::move(p));
    } else {
      bad_header("unknown keyword '" + std::string(key) + "'");
    }
  }
  if (!have_format) bad_header("no format line");
  // The body starts after the end_header line.
  std::size_t body = header_end + std::strlen("end_header");
  while (body < d.size() && (d[body] == ' ' || d[body] == '\r')) ++body;
  if (body < d.size() && d[body] == '\n') ++body;

  MeshBuilder b(path, options);
  const PlyElement* vertex_el = nullptr;
  const PlyElement* face_el = nullptr;
  int ix = -1, iy = -1, iz = -1, iface = -1;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") {
      vertex_el = &e;
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (p.is_list) continue;
        if (p.name == "x") ix = static_cast<int>(i);
        if (p.name == "y") iy = static_cast<int>(i);
        if (p.name == "z") iz = static_cast<int>(i);
      }
      if (ix < 0 || iy < 0 || iz < 0) fail(quoted(path) + ": PLY vertex element has no x, y and z properties");
      if (e.count > options.max_vertices) {
        fail(quoted(path) + " declares " + std::to_string(e.count) + " vertices, over the limit of " +
             std::to_string(options.max_vertices) + " (MeshReadOptions::max_vertices)");
      }
    } else if (e.name == "face") {
      face_el = &e;
      int lists = 0, any_list = -1;
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& p = e.properties[i];
        if (!p.is_list) continue;
        ++lists;
        any_list = static_cast<int>(i);
        if (p.name == "vertex_indices" || p.name == "vertex_index") iface = static_cast<int>(i);
      }
      if (iface < 0 && lists == 1) iface = any_list;
      if (iface < 0) fail(quoted(path) + ": PLY face element has no vertex_indices list");
      if (e.count > options.max_triangles) {
        fail(quoted(path) + " declares " + std::to_string(e.count) + " faces, over the limit of " +
             std::to_string(options.max_triangles) + " (MeshReadOptions::max_triangles)");
      }
    }
  }
  if (vertex_el == nullptr) fail(quoted(path) + " has no vertex element");
  if (face_el == nullptr) fail(quoted(path) + " has no triangles (no face element: a point cloud?)");

  const std::size_t body_bytes = d.size() - std::min(body, d.size());
  b.reserve_vertices(std::min<std::size_t>(vertex_el->count, body_bytes / 3));
  b.reserve_triangles(std::min<std::size_t>(face_el->count, body_bytes / 4));
  const std::string format_name = format == PlyFormat::kAscii    ? "PLY (ascii)"
                                  : format == PlyFormat::kLittle ? "PLY (binary little-endian)"
                                                                 : "PLY (binary big-endian)";
  auto truncated = [&](const PlyElement& e, unsigned long long got) {
    fail(quoted(path) + " is truncated: it declares " + std::to_string(e.count) + " " + e.name +
         " elements but the data ends after " + std::to_string(got));
  };
  std::vector<long long> face;
  std::vector<double> values;
  // Bad faces are reported only once the whole body has been read: data shifted by a wrong
  // count in the header looks like garbage faces, and "truncated" is the more useful message.
  std::string problem;
  auto note = [&](const std::string& what) {
    if (problem.empty()) problem = quoted(path) + ": " + what;
  };
  auto to_index = [&](double v) -> long long {
    if (!(v == std::floor(v)) || v < 0 || v >= static_cast<double>(INT_MAX)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      note(std::string("a face has vertex index ") + buf + " (face index out of range)");
      return -1;
    }
    return static_cast<long long>(v);
  };
  auto add_face = [&](unsigned long long r) {
    if (face.size() < 3) {
      note("face " + std::to_string(r + 1) + " has fewer than 3 vertices");
    } else if (std::find(face.begin(), face.end(), -1) == face.end()) {
      b.add_face(face.data(), face.size());
    }
  };
  auto list_count = [&](double v, std::size_t item_size, std::size_t available) -> std::size_t {
    if (!(v >= 0) || v != std::floor(v)) fail(quoted(path) + ": a PLY list has a negative count");
    // Every item takes at least item_size bytes (ASCII: 2), so the data bounds the count.
    if (v > static_cast<double>(available / item_size)) return SIZE_MAX;
    return static_cast<std::size_t>(v);
  };

  if (format == PlyFormat::kAscii) {
    Cursor a{d.data() + std::min(body, d.size()), d.data() + d.size()};
    for (const PlyElement& e : elements) {
      for (unsigned long long r = 0; r < e.count; ++r) {
        values.assign(e.properties.size(), 0);
        face.clear();
        for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
          const PlyProperty& p = e.properties[pi];
          double v;
          std::string_view tok = next_token(a);
          if (tok.empty()) truncated(e, r);
          if (!parse_double(tok, &v)) {
            fail(quoted(path) + " line " + std::to_string(a.line) + ": bad PLY value '" +
                 std::string(tok.substr(0, 20)) + "'");
          }
          if (!p.is_list) {
            values[pi] = v;
            continue;
          }
          const std::size_t n = list_count(v, 2, static_cast<std::size_t>(a.end - a.p));
          if (n == SIZE_MAX) truncated(e, r);
          for (std::size_t k = 0; k < n; ++k) {
            tok = next_token(a);
            if (tok.empty()) truncated(e, r);
            if (!parse_double(tok, &v)) fail(quoted(path) + " line " + std::to_string(a.line) + ": bad PLY list value");
            if (&e == face_el && static_cast<int>(pi) == iface) face.push_back(to_index(v));
          }
        }
        if (&e == vertex_el) {
          b.add_vertex(values[ix], values[iy], values[iz], "vertex", static_cast<long long>(r + 1));
        } else if (&e == face_el) {
          add_face(r);
        }
      }
    }
  } else {
    const auto* base = reinterpret_cast<const unsigned char*>(d.data());
    PlyBinary in(base + std::min(body, d.size()), base + d.size(), format == PlyFormat::kBig);
    for (const PlyElement& e : elements) {
      const bool wanted = &e == vertex_el || &e == face_el;
      std::size_t stride = 0;
      bool fixed = true;
      for (const PlyProperty& p : e.properties) {
        if (p.is_list) fixed = false;
        else stride += ply_size(p.type);
      }
      if (!wanted && fixed) {  // skipped in O(1), and a huge count fails here at once
        if (stride != 0 && e.count > in.remaining() / stride) truncated(e, in.remaining() / stride);
        in.skip(static_cast<std::size_t>(e.count) * stride);
        continue;
      }
      if (fixed && stride != 0 && e.count > in.remaining() / stride) truncated(e, in.remaining() / stride);
      for (unsigned long long r = 0; r < e.count; ++r) {
        values.assign(e.properties.size(), 0);
        face.clear();
        for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
          const PlyProperty& p = e.properties[pi];
          if (!p.is_list) {
            if (!in.has(ply_size(p.type))) truncated(e, r);
            values[pi] = in.read(p.type);
            continue;
          }
          if (!in.has(ply_size(p.count_type))) truncated(e, r);
          const std::size_t item = ply_size(p.type);
          const double declared = in.read(p.count_type);  // before remaining() is taken
          const std::size_t n = list_count(declared, item, in.remaining());
          if (n == SIZE_MAX) truncated(e, r);
          if (&e == face_el && static_cast<int>(pi) == iface) {
            for (std::size_t k = 0; k < n; ++k) face.push_back(to_index(in.read(p.type)));
          } else {
            in.skip(n * item);
          }
        }
        if (&e == vertex_el) {
          b.add_vertex(values[ix], values[iy], values[iz], "vertex", static_cast<long long>(r + 1));
        } else if (&e == face_el) {
          add_face(r);
        }
      }
    }
  }
  if (!problem.empty()) fail(problem + " (truncated, or wrong element counts in the header?)");
  return b.finish(format_name, info);
}

// ---------------------------------------------------------------------------------------------
// Voxel grids

[[noreturn]] void fail_npy(const std::string& path, const std::string& what) {
  fail(quoted(path) + " is not a usable NumPy voxel grid: " + what);
}

VoxelGrid read_npy(const std::string& path, const std::string& d, const VoxelReadOptions& options) {
  if (!starts_with(d, "\x93NUMPY")) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a NumPy .npy array");
    fail(quoted(path) + " is not a NumPy .npy file (no \\x93NUMPY signature)");
  }
  if (d.size() < 10) fail(quoted(path) + " is truncated (NumPy header cut short)");
  const auto* u = reinterpret_cast<const unsigned char*>(d.data());
  const int major = u[6];
  std::size_t header_len, header_start;
  if (major == 1) {
    header_len = std::size_t{u[8]} | (std::size_t{u[9]} << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (d.size() < 12) fail(quoted(path) + " is truncated (NumPy header cut short)");
    header_len = le32(u + 8);
    header_start = 12;
  } else {
    fail_npy(path, "unknown .npy version " + std::to_string(major));
  }
  if (header_len > d.size() - header_start) fail(quoted(path) + " is truncated (NumPy header cut short)");
  const std::string header = d.substr(header_start, header_len);
  const std::size_t data_start = header_start + header_len;

  auto value_after = [&](const char* key) -> std::size_t {
    const std::size_t k = header.find(key);
    if (k == std::string::npos) fail_npy(path, std::string("header has no ") + key);
    std::size_t p = header.find(':', k);
    if (p == std::string::npos) fail_npy(path, "bad header");
    ++p;
    while (p < header.size() && header[p] == ' ') ++p;
    return p;
  };
  // dtype
  std::size_t p = value_after("'descr'");
  if (p >= header.size() || (header[p] != '\'' && header[p] != '"')) {
    fail_npy(path, "structured dtypes are not supported (use a bool or uint8 array)");
  }
  const std::size_t q = header.find(header[p], p + 1);
  if (q == std::string::npos) fail_npy(path, "bad header");
  const std::string descr = header.substr(p + 1, q - p - 1);
  if (descr.size() < 3) fail_npy(path, "dtype '" + descr + "' is not supported");
  const char order = descr[0];
  const char kind = descr[1];
  unsigned long long item_size = 0;
  if (!parse_count(std::string_view(descr).substr(2), &item_size) ||
      std::strchr("<>|=", order) == nullptr ||
      !((kind == 'b' && item_size == 1) ||
        ((kind == 'u' || kind == 'i') &&
         (item_size == 1 || item_size == 2 || item_size == 4 || item_size == 8)) ||
        (kind == 'f' && (item_size == 4 || item_size == 8)))) {
    fail_npy(path, "dtype '" + descr + "' is not supported (use bool, an integer or a float type)");
  }
  const bool big = order == '>';
  // fortran_order
  p = value_after("'fortran_order'");
  bool fortran;
  if (header.compare(p, 4, "True") == 0) fortran = true;
  else if (header.compare(p, 5, "False") == 0) fortran = false;
  else fail_npy(path, "bad fortran_order in the header");
  // shape
  p = value_after("'shape'");
  if (p >= header.size() || header[p] != '(') fail_npy(path, "bad shape in the header");
  const std::size_t close = header.find(')', p);
  if (close == std::string::npos) fail_npy(path, "bad shape in the header");
  std::vector<unsigned long long> shape;
  {
    std::string_view s(header.data() + p + 1, close - p - 1);
    while (!s.empty()) {
      while (!s.empty() && (s.front() == ' ' || s.front() == ',')) s.remove_prefix(1);
      if (s.empty()) break;
      std::size_t e = 0;
      while (e < s.size() && s[e] != ',' && s[e] != ' ') ++e;
      unsigned long long v;
      std::string_view num = s.substr(0, e);
      if (!num.empty() && num.back() == 'L') num.remove_suffix(1);  // Python 2 longs
      if (!parse_count(num, &v)) fail_npy(path, "bad shape in the header");
      shape.push_back(v);
      s.remove_prefix(e);
    }
  }
  std::string shape_text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    shape_text += (i ? ", " : "") + std::to_string(shape[i]);
  }
  shape_text += shape.size() == 1 ? ",)" : ")";
  if (shape.size() != 3) {
    fail(quoted(path) + " has shape " + shape_text + ": a voxel grid must be a 3-D array");
  }
  unsigned long long total = 1;
  for (unsigned long long s : shape) {
    if (s == 0) fail(quoted(path) + " is an empty voxel grid (shape " + shape_text + ")");
    if (s > static_cast<unsigned long long>(INT_MAX) / 2 || total > options.max_voxels / s) {
      fail(quoted(path) + " has shape " + shape_text + ", over the limit of " +
           std::to_string(options.max_voxels) + " voxels");
    }
    total *= s;
  }
  const unsigned long long need = total * item_size;
  const std::size_t have = d.size() - data_start;
  if (have < need) {
    fail(quoted(path) + " is truncated: shape " + shape_text + " of " + descr + " needs " +
         std::to_string(need) + " data bytes, the file has " + std::to_string(have));
  }
  if (have > need) {
    fail(quoted(path) + " has " + std::to_string(have - need) +
         " bytes more than its header's shape and dtype need (not a valid .npy)");
  }
  const int s0 = static_cast<int>(shape[0]), s1 = static_cast<int>(shape[1]),
            s2 = static_cast<int>(shape[2]);
  VoxelGrid grid(s0, s1, s2);
  const unsigned char* data = u + data_start;
  const std::size_t isz = static_cast<std::size_t>(item_size);
  for (std::size_t n = 0; n < total; ++n) {
    const unsigned char* e = data + n * isz;
    bool solid;
    if (kind == 'f') {
      unsigned char b[8];
      for (std::size_t i = 0; i < isz; ++i) b[i] = big ? e[isz - 1 - i] : e[i];
      double v;
      if (isz == 4) {
        float f;
        std::memcpy(&f, b, 4);
        v = f;
      } else {
        std::memcpy(&v, b, 8);
      }
      if (std::isnan(v)) fail(quoted(path) + " contains NaN values");
      solid = v != 0;
    } else {
      solid = false;
      for (std::size_t i = 0; i < isz; ++i) solid = solid || e[i] != 0;
    }
    if (!solid) continue;
    int i, j, k;
    if (fortran) {  // first index fastest
      i = static_cast<int>(n % static_cast<std::size_t>(s0));
      j = static_cast<int>((n / static_cast<std::size_t>(s0)) % static_cast<std::size_t>(s1));
      k = static_cast<int>(n / (static_cast<std::size_t>(s0) * static_cast<std::size_t>(s1)));
    } else {  // last index fastest
      k = static_cast<int>(n % static_cast<std::size_t>(s2));
      j = static_cast<int>((n / static_cast<std::size_t>(s2)) % static_cast<std::size_t>(s1));
      i = static_cast<int>(n / (static_cast<std::size_t>(s1) * static_cast<std::size_t>(s2)));
    }
    grid.set(i, j, k);
  }
  return grid;
}

VoxelGrid read_binvox(const std::string& path, const std::string& d, const VoxelReadOptions& options) {
  if (!starts_with(d, "#binvox")) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a binvox voxel grid");
    fail(quoted(path) + " is not a binvox file (it does not start with '#binvox')");
  }
  // Header lines up to "data"; the run-length data follows its newline.
  const std::size_t data_kw = d.find("\ndata");
  if (data_kw == std::string::npos) fail(quoted(path) + " is truncated (no 'data' line in the binvox header)");
  std::size_t body = data_kw + 5;
  while (body < d.size() && d[body] == '\r') ++body;
  if (body < d.size() && d[body] == '\n') ++body;
  Cursor c{d.data(), d.data() + data_kw};
  skip_line(c);
  unsigned long long dims[3] = {0, 0, 0};
  double translate[3] = {0, 0, 0};
  double scale = 1;
  bool have_dim = false;
  auto bad = [&](const std::string& what) {
    fail(quoted(path) + " line " + std::to_string(c.line) + ": bad binvox header (" + what + ")");
  };
  while (!c.at_end()) {
    const char* lb = c.p;
    skip_line(c);
    std::string_view line(lb, static_cast<std::size_t>(c.p - lb));
    const std::string_view key = take_token(&line);
    if (key.empty()) continue;
    if (key == "dim") {
      for (auto& v : dims) {
        if (!parse_count(take_token(&line), &v) || v == 0) bad("dim needs 3 positive sizes");
      }
      have_dim = true;
    } else if (key == "translate") {
      for (double& v : translate) {
        if (!parse_double(take_token(&line), &v) || !std::isfinite(v)) bad("translate needs 3 numbers");
      }
    } else if (key == "scale") {
      if (!parse_double(take_token(&line), &scale) || !std::isfinite(scale) || scale <= 0) {
        bad("scale must be a positive number");
      }
    } else {
      bad("unknown keyword '" + std::string(key) + "'");
    }
  }
  if (!have_dim) fail(quoted(path) + ": bad binvox header (no dim line)");
  unsigned long long total = 1;
  for (unsigned long long s : dims) {
    if (s > static_cast<unsigned long long>(INT_MAX) / 2 || total > options.max_voxels / s) {
      fail(quoted(path) + " has " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
           " x " + std::to_string(dims[2]) + " voxels, over the limit of " +
           std::to_string(options.max_voxels));
    }
    total *= s;
  }
  // binvox: "dim depth height width"; the x index is the most significant, then z, then y
  // (y runs fastest): index = (x * dz + z) * dy + y.
  const int nx = static_cast<int>(dims[0]), nz = static_cast<int>(dims[1]),
            ny = static_cast<int>(dims[2]);
  const double size = scale / static_cast<double>(std::max({dims[0], dims[1], dims[2]}));
  VoxelGrid grid(nx, ny, nz, translate[0], translate[1], translate[2], size);
  const auto* u = reinterpret_cast<const unsigned char*>(d.data());
  std::size_t pos = std::min(body, d.size());
  unsigned long long n = 0;
  while (n < total) {
    if (pos + 2 > d.size()) {
      fail(quoted(path) + " is truncated: its run-length data covers " + std::to_string(n) +
           " of " + std::to_string(total) + " voxels");
    }
    const unsigned char value = u[pos];
    const unsigned long long run = u[pos + 1];
    pos += 2;
    if (run > total - n) {
      fail(quoted(path) + ": bad binvox data (a run goes past the " + std::to_string(total) +
           " voxels of the grid)");
    }
    if (value != 0) {
      for (unsigned long long m = n; m < n + run; ++m) {
        const unsigned long long y = m % static_cast<unsigned long long>(ny);
        const unsigned long long z = (m / static_cast<unsigned long long>(ny)) % static_cast<unsigned long long>(nz);
        const unsigned long long x = m / (static_cast<unsigned long long>(ny) * static_cast<unsigned long long>(nz));
        grid.set(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z));
      }
    }
    n += run;
  }
  return grid;
}

}  // namespace

bool is_mesh_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == "stl" || ext == "obj" || ext == "off" || ext == "ply";
}

bool is_voxel_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == "npy" || ext == "binvox";
}

TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options, MeshReadInfo* info) {
  const std::string ext = lower_extension(path);
  if (!is_mesh_path(path)) {
    fail(quoted(path) + ": unknown mesh format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
         "' (use .stl, .obj, .off or .ply)");
  }
  const std::string data = read_whole_file(path, options.max_file_bytes);
  if (ext == "stl") return read_stl(path, data, options, info);
  if (ext == "obj") return read_obj(path, data, options, info);
  if (ext == "off") return read_off(path, data, options, info);
  return read_ply(path, data, options, info);
}

VoxelGrid read_voxels(const std::string& path, const VoxelReadOptions& options) {
  const std::string ext = lower_extension(path);
  if (!is_voxel_path(path)) {
    fail(quoted(path) + ": unknown voxel grid format '" +
         (ext.empty() ? std::string("(no extension)") : "." + ext) + "' (use .npy or .binvox)");
  }
  const std::string data = read_whole_file(path, std::max<long long>(1LL << 20, static_cast<long long>(options.max_voxels) * 8 + (1 << 20)));
  if (ext == "npy") return read_npy(path, data, options);
  return read_binvox(path, data, options);
}

}  // namespace csgfit
