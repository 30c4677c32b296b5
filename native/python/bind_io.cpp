// Readers and converters the package offers on their own: images thresholded as the CLI does,
// meshes, voxel grids, and a mesh's solid voxels.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <string>

#include "arrays.h"
#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/io/image.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/voxelize.h"
#include "options.h"
#include "progress.h"

namespace csgfit_python {

namespace {

/// Voxelises at `size.voxel_size` (> 0), `size.resolution` voxels along the longest side
/// (> 0), or the automatic size of auto_voxel_size (both 0); `warning` gets the mesh diagnosis.
csgfit::VoxelGrid voxelize_mesh(const csgfit::TriangleMesh& mesh,
                                const csgfit::MeshFitOptions& size, std::string* warning) {
  const csgfit::MeshReport report = csgfit::analyze_mesh(mesh);
  *warning = csgfit::describe_mesh_problems(report);
  csgfit::VoxelizeOptions options;
  options.resolution = size.resolution > 0 ? size.resolution : 96;
  options.voxel_size = size.voxel_size;
  if (size.voxel_size == 0 && size.resolution == 0)
    options.voxel_size = csgfit::auto_voxel_size(report);
  return csgfit::voxelize(mesh, options);
}

}  // namespace

void bind_io(py::module_& m) {
  m.def(
      "load_bitmap",
      [](const std::string& path, int threshold, bool invert, long long max_pixels,
         int max_size) {
        const csgfit::ImageReadOptions options =
            image_read_options(threshold, invert, max_pixels, max_size);
        return mask_from_bitmap(without_gil([&] { return csgfit::read_bitmap(path, options); }));
      },
      py::arg("path"), py::arg("threshold") = -1, py::arg("invert") = false,
      py::arg("max_pixels") = 0, py::arg("max_size") = 0,
      "Reads an image file and thresholds it like the CLI: bool array, True = shape.");
  m.def(
      "threshold_grey",
      [](const U8Array& grey, int threshold, bool invert) {
        return mask_from_bitmap(csgfit::threshold_image(
            grey_from_array(grey), image_read_options(threshold, invert, 0, 0)));
      },
      py::arg("grey"), py::arg("threshold") = -1, py::arg("invert") = false,
      "Thresholds a uint8 grey array (dark = shape unless invert; threshold -1 = Otsu).");
  m.def(
      "load_mesh",
      [](const std::string& path) {
        return mesh_arrays(without_gil([&] { return csgfit::read_mesh(path); }));
      },
      py::arg("path"), "Reads an STL, OBJ, OFF or PLY mesh: (vertices (n, 3), triangles (m, 3)).");
  m.def(
      "load_voxels",
      [](const std::string& path) {
        return grid_tuple(without_gil([&] { return csgfit::read_voxels(path); }));
      },
      py::arg("path"), "Reads a .npy or .binvox voxel grid: (bool array, origin, voxel_size).");
  m.def(
      "voxelize",
      [](const F64Array& vertices, const I64Array& triangles, int resolution, double voxel_size) {
        const csgfit::MeshFitOptions size = mesh_fit_options(resolution, voxel_size);
        const csgfit::TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        std::string warning;
        const py::tuple t =
            grid_tuple(without_gil([&] { return voxelize_mesh(mesh, size, &warning); }));
        return py::make_tuple(t[0], t[1], t[2], warning);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("resolution") = 0,
      py::arg("voxel_size") = 0.0,
      "Solid voxels of a mesh as the CLI makes them: (bool array, origin, voxel_size, warning).");
}

}  // namespace csgfit_python
