// Seed 000's morphing: csgfit.morph's native half, a pair of trees of one structure and what is
// made of it (frames, JSON, .scad).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include "arrays.h"
#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/json.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "csgfit/pipeline/fit_morph.h"
#include "options.h"
#include "progress.h"
#include "scad_writer.h"
#include "scad_writer3d.h"

namespace csgfit_python {

namespace {

using namespace pybind11::literals;

/// A 2D morph with the frame that maps it to model units.
struct NativeMorph {
  csgfit::MorphResult result;
  csgfit::ModelFrame frame;
  std::string source_b;
  csgfit::TurnDirection rotate = csgfit::TurnDirection::Shortest;
};

/// A 3D morph with the lattice both shapes were scored on.
struct NativeMorph3D {
  csgfit::MorphResult3D result;
  csgfit::VoxelGrid grid;
  std::string source_a, source_b;
};

py::dict stats_dict(const csgfit::FitStats& s) {
  return py::dict("k"_a = s.k, "score"_a = s.score, "excess"_a = s.excess,
                  "uncovered"_a = s.uncovered, "primitives"_a = s.primitives, "iou"_a = s.iou,
                  "evaluations"_a = s.evaluations, "trees"_a = s.trees, "seconds"_a = s.seconds,
                  "stop_reason"_a = s.stop_reason);
}

template <typename Pair>
py::list leaves_list(const Pair& r) {
  py::list out;
  for (const csgfit::MorphLeaf& l : r.leaves) out.append(py::dict("in_a"_a = l.in_a, "in_b"_a = l.in_b));
  return out;
}

void check_t(double t) {
  if (!(t >= 0 && t <= 1)) throw csgfit::InputError("t must be between 0 and 1");
}

template <typename Native>
void bind_pair_stats(py::class_<Native>& cls) {
  cls.def("stats_a", [](const Native& n) { return stats_dict(n.result.stats_a); },
          "Stats of shape A's tree against A, as a dict.")
      .def("stats_b", [](const Native& n) { return stats_dict(n.result.stats_b); },
           "Stats of shape B's tree against B, as a dict.")
      .def("leaves", [](const Native& n) { return leaves_list(n.result); },
           "Per leaf (pre-order): {'in_a', 'in_b'}, where it is seen.");
}

void bind_morph2d(py::module_& m) {
  py::class_<NativeMorph> cls(m, "NativeMorph", "A 2D morph in pixel units; wrapped by csgfit.MorphResult.");
  bind_pair_stats(cls);
  cls.def_property_readonly("width", [](const NativeMorph& n) { return n.result.width; })
      .def_property_readonly("height", [](const NativeMorph& n) { return n.result.height; })
      .def_property_readonly("source", [](const NativeMorph& n) { return n.frame.source; })
      .def_property_readonly("source_b", [](const NativeMorph& n) { return n.source_b; })
      .def_property_readonly("pixel_size", [](const NativeMorph& n) { return n.frame.pixel_size; })
      .def_property(
          "thickness", [](const NativeMorph& n) { return n.frame.thickness; },
          [](NativeMorph& n, double v) {
            check_length("thickness", v, true);
            n.frame.thickness = v;
          },
          "Extrusion height of the .scad in mm (0 = flat 2D).")
      .def("tree_a", [](const NativeMorph& n) { return node_to_dict(n.result.a); }, "A's tree in pixel units.")
      .def("tree_b", [](const NativeMorph& n) { return node_to_dict(n.result.b); }, "B's tree in pixel units.")
      .def("to_json",
           [](const NativeMorph& n) { return csgfit::to_json_morph(n.result, n.frame, n.source_b, n.rotate); },
           "JSON text: A's document with the 'morph' object (docs/JSON_SCHEMA.md).")
      .def(
          "to_scad",
          [](const NativeMorph& n, int fn) {
            csgfit::ScadOptions o;
            o.fn = fn;
            o.width_px = n.result.width;
            o.height_px = n.result.height;
            return csgfit::to_scad_morph(n.result.a, n.result.b, n.frame, n.source_b, o, &n.result.stats_a);
          },
          py::arg("fn") = 96, "OpenSCAD source with the `morph` parameter (0 = A, 1 = B).")
      .def(
          "raster",
          [](const NativeMorph& n, double t) {
            check_t(t);
            return mask_from_bitmap(without_gil([&] {
              return csgfit::render(csgfit::interpolate(n.result.a, n.result.b, t), n.result.width,
                                    n.result.height);
            }));
          },
          py::arg("t"), "The solver's raster of the frame at t: bool array (height, width).");
  m.def(
      "morph",
      [](const U8Array& a, const U8Array& b, double k, const std::string& primitives, double time,
         int threads, std::uint64_t seed, const std::string& preset, const std::string& rotate,
         const py::object& progress, const CancelToken* cancel, double pixel_size,
         double thickness, const std::string& source_a, const std::string& source_b) {
        check_length("pixel_size", pixel_size);
        check_length("thickness", thickness, true);
        NativeMorph out;
        out.frame = csgfit::ModelFrame{pixel_size, thickness, source_a};
        out.source_b = source_b;
        csgfit::MorphOptions options;
        options.fit = fit_options(SearchArgs{k, primitives, time, threads, seed}, 0, "default");
        try {
          options.fit.search = csgfit::SearchParams::for_morph(preset);
          options.rotate = csgfit::turn_direction_from_string(rotate);
        } catch (const std::invalid_argument& e) {
          throw csgfit::InputError(e.what());
        }
        out.rotate = options.rotate;
        const csgfit::Bitmap ba = bitmap_from_mask(a), bb = bitmap_from_mask(b);
        out.result = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
          return csgfit::morph_bitmaps(ba, bb, options, callback, flag);
        });
        return out;
      },
      py::arg("a"), py::arg("b"), py::arg("k") = -1.0, py::arg("primitives") = "all",
      py::arg("time") = 10.0, py::arg("threads") = 0, py::arg("seed") = 1,
      py::arg("preset") = "default", py::arg("rotate") = "shortest",
      py::arg("progress") = py::none(), py::arg("cancel") = nullptr, py::arg("pixel_size") = 1.0,
      py::arg("thickness") = 0.0, py::arg("source_a") = "", py::arg("source_b") = "",
      "Searches two trees of one structure for masks a and b (same shape). Releases the GIL.");
  m.def(
      "is_3d_input",
      [](const std::string& path) { return csgfit::is_mesh_path(path) || csgfit::is_voxel_path(path); },
      py::arg("path"), "Whether a path names a mesh or voxel grid (by extension, as the readers do).");
  m.def("is_json_morph", &csgfit::is_json_morph, py::arg("text"),
        "Whether JSON text is a morph document (it has a 'morph' object).");
  m.def(
      "morph_from_json",
      [](const std::string& text) {
        NativeMorph out;
        out.result = csgfit::morph_from_json(text, &out.frame, &out.source_b, &out.rotate);
        return out;
      },
      py::arg("text"), "Reads a 2D morph document written by to_json into a NativeMorph.");
}

void bind_morph3d(py::module_& m) {
  py::class_<NativeMorph3D> cls(m, "NativeMorph3D", "A 3D morph; wrapped by csgfit.MorphResult.");
  bind_pair_stats(cls);
  cls.def_property_readonly("source", [](const NativeMorph3D& n) { return n.source_a; })
      .def_property_readonly("source_b", [](const NativeMorph3D& n) { return n.source_b; })
      .def("to_json",
           [](const NativeMorph3D& n) {
             return csgfit::to_json_morph3d(n.result, n.grid, n.source_a, n.source_b);
           })
      .def(
          "to_scad",
          [](const NativeMorph3D& n, int fn) {
            csgfit::ScadOptions3D o;
            o.fn = fn;
            o.source = n.source_a;
            return csgfit::to_scad_morph(n.result.a, n.result.b, n.source_b, o);
          },
          py::arg("fn") = 64)
      .def(
          "voxels",
          [](const NativeMorph3D& n, double t) {
            check_t(t);
            const csgfit::VoxelGrid v = without_gil(
                [&] { return csgfit::render(csgfit::interpolate(n.result.a, n.result.b, t), n.grid); });
            return array_from_grid(v);
          },
          py::arg("t"), "The frame at t on the shared grid: bool array (nz, ny, nx).");
  m.def(
      "morph_files3d",
      [](const std::string& a, const std::string& b, double k, const std::string& primitives,
         double time, int threads, std::uint64_t seed, int resolution, const py::object& progress,
         const CancelToken* cancel, const std::string& source_a, const std::string& source_b) {
        NativeMorph3D out;
        out.source_a = source_a;
        out.source_b = source_b;
        const auto grids = without_gil([&] {
          return csgfit::morph_grids(csgfit::read_input3d(a), csgfit::read_input3d(b), resolution);
        });
        out.grid = grids.first;
        const csgfit::FitOptions3D options = fit_options_3d(SearchArgs{k, primitives, time, threads, seed});
        out.result = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
          return csgfit::morph_voxels(grids.first, grids.second, options, callback, flag);
        });
        return out;
      },
      py::arg("a"), py::arg("b"), py::arg("k") = -1.0, py::arg("primitives") = "",
      py::arg("time") = 10.0, py::arg("threads") = 0, py::arg("seed") = 1,
      py::arg("resolution") = 0, py::arg("progress") = py::none(), py::arg("cancel") = nullptr,
      py::arg("source_a") = "", py::arg("source_b") = "",
      "Searches two trees of one structure for two meshes or voxel files.");
}

}  // namespace

void bind_morph(py::module_& m) {
  bind_morph2d(m);
  bind_morph3d(m);
}

}  // namespace csgfit_python
