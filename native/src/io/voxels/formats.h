// The voxel grid formats read_voxels dispatches to by extension. Each works on the whole file `d`
// in memory, checks each declared count against the limits before it allocates anything for it, and
// checks that the bytes the header promises are there before it reads them, so that a hostile
// header fails at once with one line (InputError naming `path`). A file of another format is
// reported as what it looks like (io/sniff.h).
#pragma once

#include <string>

#include "csgfit/io/voxels_read.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit::io_detail {

/// NumPy .npy, versions 1 to 3: a 3-D array of bool, integers or floats, C or Fortran order.
VoxelGrid read_npy(const std::string& path, const std::string& d, const VoxelReadOptions& options);

/// binvox: a text header (dim, translate, scale) and run-length data.
VoxelGrid read_binvox(const std::string& path, const std::string& d,
                      const VoxelReadOptions& options);

}  // namespace csgfit::io_detail
