// The mesh formats read_mesh dispatches to by extension. Each works on the whole file `d` in
// memory, checks each declared count against the limits before it allocates anything for it,
// and checks that the bytes the header promises are there before it reads them, so that a
// hostile header fails at once with one line (InputError naming `path`). A file of another
// format is reported as what it looks like (io/sniff.h).
#pragma once

#include <string>

#include "csgfit/io/mesh_read.h"
#include "csgfit/model/mesh.h"

namespace csgfit::io_detail {

/// Binary or ASCII STL (several solids in one file are one mesh); vertices are welded.
TriangleMesh read_stl(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info);

/// Wavefront OBJ: "v" and "f" lines (negative indices count back); the rest is skipped.
TriangleMesh read_obj(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info);

/// Text OFF, with the COFF, NOFF, STOFF... prefixes.
TriangleMesh read_off(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info);

/// PLY: ascii, binary little- and big-endian; other elements and properties are skipped.
TriangleMesh read_ply(const std::string& path, const std::string& d, const MeshReadOptions& options,
                      MeshReadInfo* info);

}  // namespace csgfit::io_detail
