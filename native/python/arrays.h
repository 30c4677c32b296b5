// numpy arrays <-> the solver's Bitmap, GreyImage, VoxelGrid and TriangleMesh, with the input
// checks that give a Python user one line naming what is wrong with an array.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <vector>

#include "csgfit/io/image.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit_python {

namespace py = pybind11;

using U8Array = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;
using F64Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using I64Array = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// An image array: rows = height, columns = width; row 0 is the top row.
csgfit::Bitmap bitmap_from_mask(const U8Array& mask);
csgfit::GreyImage grey_from_array(const U8Array& grey);
py::array_t<bool> mask_from_bitmap(const csgfit::Bitmap& bitmap);
/// A 2D tree as nested dicts in pixel units ({"op", "children"} or {"type", "cx", "cy", "w",
/// "h", "angle", "apex"}), what csgfit.tree.tree_from_pixels reads.
py::dict node_to_dict(const csgfit::Node& node);

/// Array index [i][j][k] is voxel (x, y, z) = (i, j, k), as in .npy files.
csgfit::VoxelGrid grid_from_array(const U8Array& voxels, const std::vector<double>& origin,
                                  double voxel_size);
py::array_t<bool> array_from_grid(const csgfit::VoxelGrid& grid);
/// (voxels, (x, y, z) origin, voxel_size): the Python form of a placed grid.
py::tuple grid_tuple(const csgfit::VoxelGrid& grid);

/// (n, 3) finite vertices and (m, 3) triangles indexing them.
csgfit::TriangleMesh mesh_from_arrays(const F64Array& vertices, const I64Array& triangles);
/// An (n, 3) array of finite coordinates (points or normals); `name` says which in messages.
std::vector<csgfit::Vec3> vec3s_from_array(const F64Array& a, const char* name);
/// (vertices float (n, 3), triangles int32 (m, 3)).
py::tuple mesh_arrays(const csgfit::TriangleMesh& mesh);

}  // namespace csgfit_python
