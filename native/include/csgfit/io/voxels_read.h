// Reading voxel grids: NumPy .npy and binvox. See docs/INPUTS_3D.md.
#pragma once

#include <cstddef>
#include <string>

#include "csgfit/model/voxel_grid.h"

namespace csgfit {

/// Limits for voxel grid files.
struct VoxelReadOptions {
  std::size_t max_voxels = std::size_t{1} << 30;
};

/// Reads a voxel grid: NumPy .npy (3-D; bool, int or float, non-zero = solid; C or Fortran
/// order; array index [i][j][k] is voxel (x, y, z) = (i, j, k), origin 0, voxel size 1) or
/// binvox (RLE; dim/translate/scale honoured: origin = translate, voxel size = scale / longest
/// dim). Throws InputError naming the file for a wrong shape or type, truncated or mislabelled
/// data.
VoxelGrid read_voxels(const std::string& path, const VoxelReadOptions& options = {});

/// Whether read_voxels understands the extension of path (.npy, .binvox).
bool is_voxel_path(const std::string& path);

}  // namespace csgfit
