// The 3D commands' input from a file: a triangle mesh or a voxel grid, by its extension.
#pragma once

#include <string>

#include "csgfit/pipeline/fit_mesh.h"

namespace csgfit {

/// Reads a mesh (.stl, .obj, .off, .ply: read_mesh, then analysed) or a voxel grid (.npy,
/// .binvox: read_voxels). Throws InputError for another extension and for what the readers
/// refuse.
Input3D read_input3d(const std::string& path);

}  // namespace csgfit
