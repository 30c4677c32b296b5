// The mesh and voxel fit: every 3D input (mesh arrays, voxel arrays, a mesh or voxel file)
// becomes an Input3D and goes through fit_input3d, the one place where the 3D stages are
// ordered, so Python fits exactly as `csgfit mesh` does.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/json.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "options.h"
#include "progress.h"
#include "scad_writer3d.h"

namespace csgfit_python {

namespace {

/// A 3D fit with what is shown beside it: the input voxelised in its own axes on the fit's
/// voxel size (for a voxel input, the input itself).
struct NativeResult3D {
  csgfit::MeshFitResult fit;
  csgfit::VoxelGrid preview;
  std::string source;
  std::string warning;  // what is wrong with the input mesh, if anything
};

NativeResult3D run_fit3d(const csgfit::Input3D& input, const SearchArgs& args,
                         const csgfit::MeshFitOptions& mesh_options, const py::object& progress,
                         const CancelToken* cancel, const std::string& source) {
  const csgfit::FitOptions3D options = fit_options_3d(args);
  NativeResult3D out;
  out.source = source;
  out.warning = input.warning();
  out.fit = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
    return csgfit::fit_input3d(input, options, mesh_options, callback, flag);
  });
  out.preview = without_gil([&] { return csgfit::input_voxels(input, out.fit); });
  return out;
}

csgfit::Input3D input_from_mesh(csgfit::TriangleMesh mesh) {
  return without_gil([&] { return csgfit::Input3D::from_mesh(std::move(mesh)); });
}

void bind_result(py::module_& m) {
  py::class_<NativeResult3D>(m, "NativeResult3D",
                             "A 3D fit in model units with its voxel grid; wrapped by "
                             "csgfit.FitResult3D.")
      .def_property_readonly("source", [](const NativeResult3D& r) { return r.source; })
      .def_property_readonly("warning", [](const NativeResult3D& r) { return r.warning; },
                             "What is wrong with the input mesh ('' when nothing).")
      .def_property_readonly(
          "shape",
          [](const NativeResult3D& r) {
            return py::make_tuple(r.preview.nx(), r.preview.ny(), r.preview.nz());
          },
          "Size (nx, ny, nz) of the grid of target() and raster().")
      .def_property_readonly(
          "origin",
          [](const NativeResult3D& r) {
            return py::make_tuple(r.preview.origin_x(), r.preview.origin_y(),
                                  r.preview.origin_z());
          },
          "Model coordinates of that grid's corner (voxel (0, 0, 0)'s low corner).")
      .def_property_readonly(
          "voxel_size", [](const NativeResult3D& r) { return r.preview.voxel_size(); },
          "Voxel edge in model units.")
      .def(
          "to_json",
          [](const NativeResult3D& r) {
            return csgfit::to_json3d(r.fit.fit, r.fit.grid, r.source, r.fit.frame);
          },
          "The 3D JSON document (docs/JSON_SCHEMA.md, 3D documents), as `csgfit mesh` writes it.")
      .def(
          "target", [](const NativeResult3D& r) { return array_from_grid(r.preview); },
          "The fitted input's voxels: bool array [i, j, k] = voxel (x, y, z).")
      .def(
          "raster",
          [](const NativeResult3D& r) {
            return array_from_grid(
                without_gil([&] { return csgfit::render(r.fit.fit.tree, r.preview); }));
          },
          "The solver's voxels of the tree on the same grid (bool array [i, j, k]).")
      .def(
          "to_scad",
          [](const NativeResult3D& r, int fn) {
            if (fn < 3) throw csgfit::InputError("fn must be >= 3");
            csgfit::ScadOptions3D options;
            options.fn = fn;
            options.source = r.source;
            return csgfit::to_scad(r.fit.fit.tree, options);
          },
          py::arg("fn") = 64, "OpenSCAD 2021.01 source of the tree (model units).");
}

/// Defines a 3D fit: its input's arguments, then the search arguments every 3D fit shares
/// (with the CLI's defaults: no torus, 30 s).
template <class Fit, class... InputArgs>
void def_fit3d(py::module_& m, const char* name, Fit&& fit, const char* doc,
               InputArgs... input_args) {
  m.def(name, std::forward<Fit>(fit), input_args..., py::arg("k") = -1.0,
        py::arg("primitives") = "box,sphere,cylinder,cone,ellipsoid,prism",
        py::arg("time") = 30.0, py::arg("threads") = 0, py::arg("seed") = 1,
        py::arg("progress") = py::none(), py::arg("cancel") = nullptr, py::arg("source") = "",
        doc);
}

}  // namespace

void bind_3d(py::module_& m) {
  bind_result(m);
  m.def(
      "sweeps_json",
      [](const std::string& document) {
        return csgfit::to_json_sweeps(csgfit::from_json3d(document));
      },
      py::arg("document"),
      "The \"sweeps\" block (a JSON array) of a 3D document's tree, as to_json writes it.");
  def_fit3d(
      m, "fit_mesh_arrays",
      [](const F64Array& vertices, const I64Array& triangles, int resolution, double voxel_size,
         double k, const std::string& primitives, double time, int threads, std::uint64_t seed,
         const py::object& progress, const CancelToken* cancel, const std::string& source) {
        const csgfit::MeshFitOptions mesh_options = mesh_fit_options(resolution, voxel_size);
        const csgfit::Input3D input = input_from_mesh(mesh_from_arrays(vertices, triangles));
        return run_fit3d(input, SearchArgs{k, primitives, time, threads, seed}, mesh_options,
                         progress, cancel, source);
      },
      "Fits a 3D CSG tree to a mesh as `csgfit mesh` does (GIL released while solving).",
      py::arg("vertices"), py::arg("triangles"), py::arg("resolution") = 0,
      py::arg("voxel_size") = 0.0);
  def_fit3d(
      m, "fit_voxels",
      [](const U8Array& voxels, const std::vector<double>& origin, double voxel_size, double k,
         const std::string& primitives, double time, int threads, std::uint64_t seed,
         const py::object& progress, const CancelToken* cancel, const std::string& source) {
        const csgfit::Input3D input =
            csgfit::Input3D::from_voxels(grid_from_array(voxels, origin, voxel_size));
        return run_fit3d(input, SearchArgs{k, primitives, time, threads, seed}, {}, progress,
                         cancel, source);
      },
      "Fits a 3D CSG tree to a voxel array ([i, j, k] = voxel (x, y, z), nonzero = solid).",
      py::arg("voxels"), py::arg("origin") = std::vector<double>{0, 0, 0},
      py::arg("voxel_size") = 1.0);
  def_fit3d(
      m, "fit_file",
      [](const std::string& path, int resolution, double voxel_size, double k,
         const std::string& primitives, double time, int threads, std::uint64_t seed,
         const py::object& progress, const CancelToken* cancel, const std::string& source) {
        const csgfit::MeshFitOptions mesh_options = mesh_fit_options(resolution, voxel_size);
        const csgfit::Input3D input = without_gil([&] { return csgfit::read_input3d(path); });
        return run_fit3d(input, SearchArgs{k, primitives, time, threads, seed}, mesh_options,
                         progress, cancel, source);
      },
      "Fits a mesh (.stl, .obj, .off, .ply) or a voxel grid (.npy, .binvox, fitted as it is).",
      py::arg("path"), py::arg("resolution") = 0, py::arg("voxel_size") = 0.0);
}

}  // namespace csgfit_python
