// Reading triangle meshes: STL (ASCII and binary), OBJ, OFF and PLY. See docs/INPUTS_3D.md.
#pragma once

#include <cstddef>
#include <string>

#include "csgfit/model/mesh.h"

namespace csgfit {

/// Limits applied while reading. Declared counts above them are refused before anything is
/// allocated, so a header that claims 10^12 faces fails at once.
struct MeshReadOptions {
  std::size_t max_triangles = 5'000'000;
  std::size_t max_vertices = 15'000'000;
  /// Files larger than this are refused before they are read (bytes).
  long long max_file_bytes = 2LL << 30;
};

/// What read_mesh found besides the mesh itself.
struct MeshReadInfo {
  std::string format;                   ///< "STL (ASCII)", "STL (binary)", "OBJ", "OFF", "PLY (ascii)", ...
  std::size_t faces_read = 0;           ///< faces in the file (polygons count once)
  std::size_t degenerate_dropped = 0;   ///< zero-area triangles left out of the mesh
};

/// Reads a mesh; the extension (.stl, .obj, .off, .ply, case-insensitive) decides the format,
/// and the content is checked against it, so a PNG renamed .stl is reported as such.
/// Polygons are fan-triangulated, STL vertices are welded by exact position, zero-area
/// triangles are dropped (counted in *info). Throws InputError (one line, naming the file) for
/// a missing, empty, truncated, mislabelled or oversized file, NaN/inf coordinates, face indices
/// out of range, or a mesh without triangles.
TriangleMesh read_mesh(const std::string& path, const MeshReadOptions& options = {},
                       MeshReadInfo* info = nullptr);

/// Whether read_mesh understands the extension of path.
bool is_mesh_path(const std::string& path);

}  // namespace csgfit
