#include "io/mesh/mesh_builder.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "io/input_file.h"
#include "model/triangle_geometry.h"

namespace csgfit::io_detail {

void MeshBuilder::add_vertex(double x, double y, double z, const char* what, long long number) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    fail(quoted(path_) + " " + what + " " + std::to_string(number) + ": vertex " +
         std::to_string(mesh_.vertices.size() + 1) +
         " has a non-finite coordinate (NaN or infinity)");
  }
  if (mesh_.vertices.size() >= options_.max_vertices) {
    fail(quoted(path_) + " has more than " + std::to_string(options_.max_vertices) +
         " vertices, over the limit");
  }
  mesh_.vertices.push_back({x, y, z});
}

int MeshBuilder::add_welded_vertex(double x, double y, double z, const char* what,
                                   long long number) {
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

void MeshBuilder::add_face(const long long* indices, std::size_t n) {
  ++faces_;
  if (n < 3) {
    fail(quoted(path_) + ": face " + std::to_string(faces_) + " has fewer than 3 vertices");
  }
  if (mesh_.triangles.size() + (n - 2) > options_.max_triangles) fail_too_many_triangles();
  for (std::size_t i = 0; i < n; ++i) {
    if (indices[i] < 0 || indices[i] >= INT_MAX) fail_index(indices[i]);
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    mesh_.triangles.push_back({static_cast<int>(indices[0]), static_cast<int>(indices[i]),
                               static_cast<int>(indices[i + 1])});
  }
}

void MeshBuilder::fail_too_many_triangles() const {
  fail(quoted(path_) + " has more than " + std::to_string(options_.max_triangles) +
       " triangles, over the limit (MeshReadOptions::max_triangles)");
}

void MeshBuilder::fail_index(long long index) const {
  fail(quoted(path_) + ": face " + std::to_string(faces_) + " refers to vertex " +
       std::to_string(index + 1) + " (1-based) but there are " +
       count_text(mesh_.vertices.size(), "vertex") + " (face index out of range)");
}

TriangleMesh MeshBuilder::finish(const std::string& format, MeshReadInfo* info) {
  const std::size_t nv = mesh_.vertices.size();
  std::size_t kept = 0;
  std::size_t dropped = 0;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tri = mesh_.triangles[t];
    for (int v : tri) {
      if (static_cast<std::size_t>(v) >= nv) {
        fail(quoted(path_) + ": a face refers to vertex " + std::to_string(v + 1) +
             " (1-based) but there are " + count_text(nv, "vertex") + " (face index out of range)");
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

std::size_t MeshBuilder::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = 1469598103934665603ULL;
  for (double v : {k.x, k.y, k.z}) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    h = (h ^ bits) * 1099511628211ULL;
    h ^= h >> 29;
  }
  return static_cast<std::size_t>(h);
}

// Zero area up to rounding: repeated vertices or (nearly exactly) collinear ones.
bool MeshBuilder::degenerate(const std::array<int, 3>& t) const {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const auto& a = mesh_.vertices[t[0]];
  const geometry::Point u = geometry::minus(mesh_.vertices[t[1]], a);
  const geometry::Point v = geometry::minus(mesh_.vertices[t[2]], a);
  const geometry::Point n = geometry::cross(u, v);
  const double e2 = std::max(geometry::dot(u, u), geometry::dot(v, v));
  return geometry::dot(n, n) <= 1e-24 * e2 * e2;
}

}  // namespace csgfit::io_detail
