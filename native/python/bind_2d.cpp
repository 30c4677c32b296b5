// The bitmap fit: csgfit.fit_image's native half, its result in pixel units, and the 2D JSON
// reader (csgfit.load_json).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstring>
#include <iterator>
#include <string>

#include "arrays.h"
#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "csgfit/model/frame.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "options.h"
#include "progress.h"
#include "scad_writer.h"

namespace csgfit_python {

using namespace pybind11::literals;

py::dict node_to_dict(const csgfit::Node& node) {
  if (node.is_leaf()) {
    const csgfit::Primitive& p = node.primitive;
    return py::dict("type"_a = std::string(csgfit::to_string(p.kind)), "cx"_a = p.cx,
                    "cy"_a = p.cy, "w"_a = p.w, "h"_a = p.h, "angle"_a = p.angle,
                    "apex"_a = p.apex);
  }
  py::list children;
  for (const csgfit::Node& child : node.children) children.append(node_to_dict(child));
  return py::dict("op"_a = std::string(csgfit::to_string(node.kind)), "children"_a = children);
}

namespace {

using namespace pybind11::literals;

/// A fit (or a loaded JSON file) with the frame that maps it to model units and, when known,
/// the target bitmap it was fitted to.
struct NativeResult {
  csgfit::FitResult result;
  csgfit::ModelFrame frame;
  csgfit::Bitmap target;  // empty for results read from JSON
};

py::dict stats_to_dict(const csgfit::FitStats& s) {
  return py::dict("k"_a = s.k, "score"_a = s.score, "excess"_a = s.excess,
                  "uncovered"_a = s.uncovered, "primitives"_a = s.primitives, "iou"_a = s.iou,
                  "evaluations"_a = s.evaluations, "trees"_a = s.trees, "seconds"_a = s.seconds,
                  "stop_reason"_a = s.stop_reason);
}

/// A tree of a result with its stats.
struct TreeRef {
  const csgfit::Node& tree;
  const csgfit::FitStats& stats;
};

/// index -1 is the best tree, 0..n-1 the alternatives.
TreeRef tree_at(const NativeResult& r, int index) {
  if (index == -1) return {r.result.tree, r.result.stats};
  if (index < 0 || static_cast<std::size_t>(index) >= r.result.alternatives.size()) {
    throw py::index_error("no alternative " + std::to_string(index) + " (this result has " +
                          std::to_string(r.result.alternatives.size()) + ")");
  }
  const csgfit::FitTree& alt = r.result.alternatives[static_cast<std::size_t>(index)];
  return {alt.tree, alt.stats};
}

NativeResult run_fit(const U8Array& mask, const SearchArgs& args, int alternatives,
                     const std::string& quality, const py::object& progress,
                     const CancelToken* cancel, const csgfit::ModelFrame& frame) {
  check_length("pixel_size", frame.pixel_size);
  check_length("thickness", frame.thickness, true);
  NativeResult out;
  out.target = bitmap_from_mask(mask);
  out.frame = frame;
  const csgfit::FitOptions options = fit_options(args, alternatives, quality);
  out.result = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
    return csgfit::fit_bitmap(out.target, options, callback, flag);
  });
  return out;
}

void bind_frame(py::class_<NativeResult>& cls) {
  cls.def_property_readonly("width", [](const NativeResult& r) { return r.result.width; },
                            "Canvas width in pixels.")
      .def_property_readonly("height", [](const NativeResult& r) { return r.result.height; },
                             "Canvas height in pixels.")
      .def_property(
          "pixel_size", [](const NativeResult& r) { return r.frame.pixel_size; },
          [](NativeResult& r, double v) {
            check_length("pixel_size", v);
            r.frame.pixel_size = v;
          },
          "Model units (mm) per pixel.")
      .def_property(
          "thickness", [](const NativeResult& r) { return r.frame.thickness; },
          [](NativeResult& r, double v) {
            check_length("thickness", v, true);
            r.frame.thickness = v;
          },
          "Extrusion height in model units (0 = a 2D result).")
      .def_property_readonly("source", [](const NativeResult& r) { return r.frame.source; },
                             "Input file name (empty for arrays).")
      .def_property_readonly(
          "alternative_count", [](const NativeResult& r) { return r.result.alternatives.size(); },
          "Number of alternative trees.");
}

void bind_trees(py::class_<NativeResult>& cls) {
  cls.def(
         "tree",
         [](const NativeResult& r, int index) { return node_to_dict(tree_at(r, index).tree); },
         py::arg("index") = -1,
         "Tree as nested dicts in pixel units (index -1 = best, 0.. = alternatives).")
      .def(
          "stats",
          [](const NativeResult& r, int index) { return stats_to_dict(tree_at(r, index).stats); },
          py::arg("index") = -1, "Stats of a tree as a dict.")
      .def(
          "raster",
          [](const NativeResult& r, int index) {
            const csgfit::Node& tree = tree_at(r, index).tree;
            return mask_from_bitmap(
                without_gil([&] { return csgfit::render(tree, r.result.width, r.result.height); }));
          },
          py::arg("index") = -1,
          "The solver's raster of a tree: bool array (height, width), row 0 at the top.")
      .def(
          "target",
          [](const NativeResult& r) -> py::object {
            if (r.target.empty()) return py::none();
            return mask_from_bitmap(r.target);
          },
          "The bitmap that was fitted (bool array, True = shape), or None for loaded JSON.");
}

void bind_writers(py::class_<NativeResult>& cls) {
  cls.def(
         "to_json", [](const NativeResult& r) { return csgfit::to_json(r.result, r.frame); },
         "JSON text (schema in docs/JSON_SCHEMA.md) of the result and its alternatives.")
      .def(
          "to_scad",
          [](const NativeResult& r, int index, int fn) {
            if (fn < 3) throw csgfit::InputError("fn must be >= 3");
            const TreeRef t = tree_at(r, index);
            csgfit::ScadOptions options;
            options.fn = fn;
            return csgfit::to_scad(t.tree, r.frame, options, &t.stats);
          },
          py::arg("index") = -1, py::arg("fn") = 96,
          "OpenSCAD 2021.01 source of a tree in model units.");
}

NativeResult from_json_text(const std::string& text) {
  NativeResult r;
  r.result = csgfit::from_json(text, &r.frame);
  return r;
}

}  // namespace

void bind_2d(py::module_& m) {
  py::class_<NativeResult> cls(m, "NativeResult",
                               "A fitted (or loaded) result in the solver's pixel units; "
                               "wrapped by csgfit.FitResult.");
  bind_frame(cls);
  bind_trees(cls);
  bind_writers(cls);

  m.def(
      "fit",
      [](const U8Array& mask, double k, const std::string& primitives, double time, int threads,
         std::uint64_t seed, int alternatives, const std::string& quality,
         const py::object& progress, const CancelToken* cancel, double pixel_size,
         double thickness, const std::string& source) {
        return run_fit(mask, SearchArgs{k, primitives, time, threads, seed}, alternatives,
                       quality, progress, cancel, csgfit::ModelFrame{pixel_size, thickness, source});
      },
      py::arg("mask"), py::arg("k") = -1.0, py::arg("primitives") = "all", py::arg("time") = 10.0,
      py::arg("threads") = 0, py::arg("seed") = 1, py::arg("alternatives") = 0,
      py::arg("quality") = "default", py::arg("progress") = py::none(),
      py::arg("cancel") = nullptr, py::arg("pixel_size") = 1.0, py::arg("thickness") = 0.0,
      py::arg("source") = "",
      "Fits a CSG tree to a mask (2D uint8/bool array, nonzero = shape). Releases the GIL "
      "while solving; progress(FitProgress) may return False to cancel.");
  m.def("from_json", &from_json_text, py::arg("text"),
        "Parses JSON written by to_json into a NativeResult.");
  m.def("read_json_file", &csgfit::read_json_file, py::arg("path"),
        "The text of a .json file, read under the documents' size limit.");
  m.def("default_k", &csgfit::default_k, py::arg("width"), py::arg("height"),
        py::arg("k_at_128") = csgfit::SearchParams{}.k_at_128,
        "Size weight k used when none is given: k_at_128 (11; the paper's preset 25) at "
        "128 x 128, scaled to the pixel count.");
}

}  // namespace csgfit_python
