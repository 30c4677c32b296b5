// numpy <-> the solver's rasters and meshes. The checks come first so that a bad array is
// refused before anything is allocated for it.
#include "arrays.h"

#include <cmath>
#include <string>

#include "csgfit/error.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/range_read.h"

namespace csgfit_python {

namespace {

/// Voxel arrays larger than this are refused (the CLI's voxelisation limit).
constexpr std::size_t kMaxVoxels = std::size_t{1} << 27;

std::string dimensions(py::ssize_t n) {
  return std::to_string(n) + " dimension" + (n == 1 ? "" : "s");
}

void check_image_array(const py::array& a) {
  if (a.ndim() != 2)
    throw csgfit::InputError("expected a 2D array (height x width), got " + dimensions(a.ndim()));
  const std::string size = std::to_string(a.shape(1)) + " x " + std::to_string(a.shape(0));
  if (a.shape(0) == 0 || a.shape(1) == 0)
    throw csgfit::InputError("empty image (" + size + " pixels)");
  if (a.shape(0) > 1 << 20 || a.shape(1) > 1 << 20)
    throw csgfit::InputError("image too large (" + size + " pixels)");
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void check_grid_frame(const std::vector<double>& origin, double voxel_size) {
  if (origin.size() != 3) throw csgfit::InputError("origin must be three numbers (x, y, z)");
  for (double v : origin)
    if (!std::isfinite(v)) throw csgfit::InputError("origin must be finite");
  if (!std::isfinite(voxel_size) || voxel_size <= 0)
    throw csgfit::InputError("voxel_size must be a positive number");
}

void check_mesh_arrays(const F64Array& vertices, const I64Array& triangles) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw csgfit::InputError("vertices must be an (n, 3) array");
  if (triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw csgfit::InputError("triangles must be an (m, 3) array of vertex indices");
  const csgfit::MeshReadOptions limits;
  if (static_cast<std::size_t>(vertices.shape(0)) > limits.max_vertices ||
      static_cast<std::size_t>(triangles.shape(0)) > limits.max_triangles)
    throw csgfit::InputError("mesh too large (" + std::to_string(vertices.shape(0)) +
                             " vertices, " + std::to_string(triangles.shape(0)) + " triangles)");
  if (triangles.shape(0) == 0) throw csgfit::InputError("the mesh has no triangles");
}

}  // namespace

csgfit::Bitmap bitmap_from_mask(const U8Array& mask) {
  check_image_array(mask);
  const int h = static_cast<int>(mask.shape(0));
  const int w = static_cast<int>(mask.shape(1));
  csgfit::Bitmap bitmap(w, h);
  auto v = mask.unchecked<2>();
  for (int row = 0; row < h; ++row)
    for (int col = 0; col < w; ++col)
      if (v(row, col) != 0) bitmap.set(col, row);
  return bitmap;
}

csgfit::GreyImage grey_from_array(const U8Array& grey) {
  check_image_array(grey);
  csgfit::GreyImage image;
  image.height = static_cast<int>(grey.shape(0));
  image.width = static_cast<int>(grey.shape(1));
  image.grey.assign(grey.data(), grey.data() + grey.size());
  return image;
}

py::array_t<bool> mask_from_bitmap(const csgfit::Bitmap& bitmap) {
  py::array_t<bool> out({static_cast<py::ssize_t>(bitmap.height()),
                         static_cast<py::ssize_t>(bitmap.width())});
  auto v = out.mutable_unchecked<2>();
  for (int row = 0; row < bitmap.height(); ++row)
    for (int col = 0; col < bitmap.width(); ++col) v(row, col) = bitmap.get(col, row);
  return out;
}

csgfit::VoxelGrid grid_from_array(const U8Array& voxels, const std::vector<double>& origin,
                                  double voxel_size) {
  if (voxels.ndim() != 3)
    throw csgfit::InputError("expected a 3D voxel array (nx x ny x nz), got " +
                             dimensions(voxels.ndim()));
  check_grid_frame(origin, voxel_size);
  const py::ssize_t nx = voxels.shape(0), ny = voxels.shape(1), nz = voxels.shape(2);
  if (nx == 0 || ny == 0 || nz == 0) throw csgfit::InputError("empty voxel array");
  if (static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) * static_cast<std::size_t>(nz) >
      kMaxVoxels)
    throw csgfit::InputError("voxel array too large (" + std::to_string(nx) + " x " +
                             std::to_string(ny) + " x " + std::to_string(nz) + ")");
  csgfit::VoxelGrid grid(static_cast<int>(nx), static_cast<int>(ny), static_cast<int>(nz),
                         origin[0], origin[1], origin[2], voxel_size);
  auto v = voxels.unchecked<3>();
  for (py::ssize_t k = 0; k < nz; ++k)
    for (py::ssize_t j = 0; j < ny; ++j)
      for (py::ssize_t i = 0; i < nx; ++i)
        if (v(i, j, k) != 0)
          grid.set(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
  return grid;
}

py::array_t<bool> array_from_grid(const csgfit::VoxelGrid& grid) {
  py::array_t<bool> out({static_cast<py::ssize_t>(grid.nx()), static_cast<py::ssize_t>(grid.ny()),
                         static_cast<py::ssize_t>(grid.nz())});
  auto v = out.mutable_unchecked<3>();
  for (int k = 0; k < grid.nz(); ++k)
    for (int j = 0; j < grid.ny(); ++j)
      for (int i = 0; i < grid.nx(); ++i) v(i, j, k) = grid.get(i, j, k);
  return out;
}

py::tuple grid_tuple(const csgfit::VoxelGrid& grid) {
  return py::make_tuple(array_from_grid(grid),
                        py::make_tuple(grid.origin_x(), grid.origin_y(), grid.origin_z()),
                        grid.voxel_size());
}

csgfit::TriangleMesh mesh_from_arrays(const F64Array& vertices, const I64Array& triangles) {
  check_mesh_arrays(vertices, triangles);
  csgfit::TriangleMesh mesh;
  auto v = vertices.unchecked<2>();
  mesh.vertices.resize(static_cast<std::size_t>(vertices.shape(0)));
  for (py::ssize_t i = 0; i < vertices.shape(0); ++i)
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(v(i, a)))
        throw csgfit::InputError("vertex " + std::to_string(i) + " is not finite");
      mesh.vertices[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] = v(i, a);
    }
  auto t = triangles.unchecked<2>();
  mesh.triangles.resize(static_cast<std::size_t>(triangles.shape(0)));
  for (py::ssize_t i = 0; i < triangles.shape(0); ++i)
    for (int a = 0; a < 3; ++a) {
      const std::int64_t idx = t(i, a);
      if (idx < 0 || idx >= vertices.shape(0))
        throw csgfit::InputError("triangle " + std::to_string(i) + " refers to vertex " +
                                 std::to_string(idx) + " (the mesh has " +
                                 std::to_string(vertices.shape(0)) + ")");
      mesh.triangles[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] =
          static_cast<int>(idx);
    }
  return mesh;
}

std::vector<csgfit::Vec3> vec3s_from_array(const F64Array& a, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw csgfit::InputError(std::string(name) + " must be an (n, 3) array, got shape " +
                             shape_text(a));
  const csgfit::RangeReadOptions limits;
  if (a.shape(0) > limits.max_points)
    throw csgfit::InputError(std::string(name) + ": too many points (" +
                             std::to_string(a.shape(0)) + ", at most " +
                             std::to_string(limits.max_points) + ")");
  auto v = a.unchecked<2>();
  std::vector<csgfit::Vec3> out(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(v(i, k)))
        throw csgfit::InputError(std::string(name) + " row " + std::to_string(i) +
                                 " is not finite");
      out[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = v(i, k);
    }
  return out;
}

py::tuple mesh_arrays(const csgfit::TriangleMesh& mesh) {
  py::array_t<double> vertices(
      {static_cast<py::ssize_t>(mesh.vertices.size()), static_cast<py::ssize_t>(3)});
  py::array_t<std::int32_t> triangles(
      {static_cast<py::ssize_t>(mesh.triangles.size()), static_cast<py::ssize_t>(3)});
  auto v = vertices.mutable_unchecked<2>();
  auto t = triangles.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a) v(static_cast<py::ssize_t>(i), a) = mesh.vertices[i][a];
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int a = 0; a < 3; ++a) t(static_cast<py::ssize_t>(i), a) = mesh.triangles[i][a];
  return py::make_tuple(vertices, triangles);
}

}  // namespace csgfit_python
