// What every mesh reader hands its vertices and faces to: checks them against the limits,
// welds STL vertices, fan-triangulates polygons, drops degenerate triangles and counts.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/io/mesh_read.h"
#include "csgfit/model/mesh.h"

namespace csgfit::io_detail {

/// Collects one file's mesh. Failures throw InputError naming `path`.
class MeshBuilder {
 public:
  MeshBuilder(const std::string& path, const MeshReadOptions& options)
      : path_(path), options_(options) {}

  void reserve_vertices(std::size_t n) { mesh_.vertices.reserve(n); }
  void reserve_triangles(std::size_t n) { mesh_.triangles.reserve(n); }

  std::size_t vertex_count() const { return mesh_.vertices.size(); }

  /// A vertex; `what number` says where in the file (e.g. "line 12"), formatted on failure only.
  void add_vertex(double x, double y, double z, const char* what, long long number);

  /// A welded vertex (STL shares none): equal positions get one index, which is returned.
  int add_welded_vertex(double x, double y, double z, const char* what, long long number);

  /// A face given by n 0-based vertex indices, checked against the vertex count in finish()
  /// (OBJ and PLY may list faces before all vertices).
  void add_face(const long long* indices, std::size_t n);

  [[noreturn]] void fail_too_many_triangles() const;

  /// The mesh without degenerate triangles; `format` and the counts go to *info.
  TriangleMesh finish(const std::string& format, MeshReadInfo* info);

 private:
  [[noreturn]] void fail_index(long long index) const;
  bool degenerate(const std::array<int, 3>& t) const;
  /// Refuses a mesh whose size is outside [kMinExtent, kMaxExtent]: beyond it the fit's
  /// volumes and distances lose all precision or overflow.
  void check_extent() const;
  static constexpr double kMinExtent = 1e-9, kMaxExtent = 1e12;

  const std::string& path_;
  const MeshReadOptions& options_;
  TriangleMesh mesh_;
  std::size_t faces_ = 0;
  // The welded vertices: an open-addressed table, kept at most half full, of entries (high
  // half of the position's hash) << 32 | vertex index. A node-based map spent a third of a
  // 1M-triangle STL's read on allocation.
  static constexpr std::uint64_t kFreeSlot = ~std::uint64_t{0};
  std::vector<std::uint64_t> weld_;
  void grow_weld_table();
};

}  // namespace csgfit::io_detail
