#include "io/mesh/mesh_builder.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
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
  const geometry::Point p{x + 0.0, y + 0.0, z + 0.0};  // -0 and +0 are one position
  if (2 * (mesh_.vertices.size() + 1) > weld_.size()) grow_weld_table();
  const std::size_t mask = weld_.size() - 1;
  const std::uint64_t hash = geometry::position_hash(p);
  const std::uint64_t tag = hash & ~std::uint64_t{0xffffffff};
  std::size_t slot = hash & mask;
  for (; weld_[slot] != kFreeSlot; slot = (slot + 1) & mask) {
    // The tag (the hash's high half) spares the vertex lookup, a cache miss, on most probes.
    const std::uint64_t entry = weld_[slot];
    const int v = static_cast<int>(entry & 0xffffffff);
    if ((entry & ~std::uint64_t{0xffffffff}) == tag && mesh_.vertices[v] == p) return v;
  }
  add_vertex(p[0], p[1], p[2], what, number);
  const int index = static_cast<int>(mesh_.vertices.size() - 1);
  weld_[slot] = tag | static_cast<std::uint32_t>(index);
  return index;
}

void MeshBuilder::grow_weld_table() {
  std::vector<std::uint64_t> old = std::move(weld_);
  weld_.assign(std::max<std::size_t>(1024, old.size() * 2), kFreeSlot);
  const std::size_t mask = weld_.size() - 1;
  for (std::uint64_t entry : old) {
    if (entry == kFreeSlot) continue;
    const int v = static_cast<int>(entry & 0xffffffff);
    std::size_t slot = geometry::position_hash(mesh_.vertices[v]) & mask;
    while (weld_[slot] != kFreeSlot) slot = (slot + 1) & mask;
    weld_[slot] = entry;
  }
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
  check_extent();
  if (info) {
    info->format = format;
    info->faces_read = faces_;
    info->degenerate_dropped = dropped;
  }
  return std::move(mesh_);
}

void MeshBuilder::check_extent() const {
  double lo[3], hi[3];
  for (int i = 0; i < 3; ++i) lo[i] = hi[i] = mesh_.vertices[mesh_.triangles[0][0]][i];
  for (const auto& tri : mesh_.triangles)
    for (int v : tri)
      for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], mesh_.vertices[v][i]);
        hi[i] = std::max(hi[i], mesh_.vertices[v][i]);
      }
  double extent = 0;
  for (int i = 0; i < 3; ++i) extent = std::max(extent, hi[i] - lo[i]);
  if (extent >= kMinExtent && extent <= kMaxExtent) return;
  char size[32];
  std::snprintf(size, sizeof size, "%.3g", extent);
  fail(quoted(path_) + " is " + size + " units across: csgfit fits parts from 1e-09 to 1e+12 "
       "units across (scale the mesh)");
}

// Zero area up to rounding: repeated vertices or (nearly exactly) collinear ones.
bool MeshBuilder::degenerate(const std::array<int, 3>& t) const {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const auto& a = mesh_.vertices[t[0]];
  geometry::Point u = geometry::minus(mesh_.vertices[t[1]], a);
  geometry::Point v = geometry::minus(mesh_.vertices[t[2]], a);
  // Scaled to unit size first: at 1e307 the products overflow, at 1e-300 they underflow.
  double largest = 0;
  for (int i = 0; i < 3; ++i) largest = std::max({largest, std::fabs(u[i]), std::fabs(v[i])});
  if (!(largest > 0) || !std::isfinite(largest)) return true;
  for (int i = 0; i < 3; ++i) {
    u[i] /= largest;
    v[i] /= largest;
  }
  const geometry::Point n = geometry::cross(u, v);
  const double e2 = std::max(geometry::dot(u, u), geometry::dot(v, v));
  return geometry::dot(n, n) <= 1e-24 * e2 * e2;
}

}  // namespace csgfit::io_detail
