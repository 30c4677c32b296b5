// The range fit (seed 002): range images, point files and point arrays go through fit_range,
// the one place where the range stages are ordered, so Python fits exactly as `csgfit range`
// does. The result keeps the first view's scan, which the segmentation preview is drawn on.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/features/point_normals.h"
#include "csgfit/io/json.h"
#include "csgfit/io/range_preview.h"
#include "csgfit/io/range_read.h"
#include "csgfit/pipeline/fit_range.h"
#include "csgfit/seed/precedence_graph.h"
#include "options.h"
#include "progress.h"
#include "tree_outputs.h"

namespace csgfit_python {

namespace {

using OptionalNumber = std::optional<double>;

struct NativeRangeResult {
  csgfit::RangeFitResult fit;
  std::vector<std::string> sources;
  std::optional<csgfit::RangeScan> first_view;  // only when it has a camera and pixels
};

/// The search arguments of a range fit, checked as the other fits check theirs.
struct RangeSearch {
  std::string primitives;
  double time = 20;
  int threads = 0;
  std::uint64_t seed = 1;
};

csgfit::RangeFitOptions range_options(const RangeSearch& s) {
  if (!std::isfinite(s.time) || s.time <= 0)
    throw csgfit::InputError("time must be a positive number of seconds");
  if (s.threads < 0) throw csgfit::InputError("threads must be >= 0 (0 = all cores)");
  csgfit::RangeFitOptions options;
  try {
    options.primitives = csgfit::PrimitiveSet3D::parse(s.primitives);
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(std::string("primitives: ") + e.what());
  }
  if (options.primitives.empty()) throw csgfit::InputError("no primitive types selected");
  options.time_limit = s.time;
  options.threads = s.threads;
  options.seed = s.seed;
  return options;
}

/// The intrinsics that replace or stand in for a sidecar: lengths positive, the principal
/// point finite (it may lie outside the image).
csgfit::RangeIntrinsics intrinsics(OptionalNumber fx, OptionalNumber fy, OptionalNumber cx,
                                   OptionalNumber cy, OptionalNumber pixel_size,
                                   OptionalNumber depth_unit) {
  const std::pair<const char*, OptionalNumber> lengths[] = {
      {"fx", fx}, {"fy", fy}, {"pixel_size", pixel_size}, {"depth_unit", depth_unit}};
  for (const auto& [name, v] : lengths)
    if (v) check_length(name, *v);
  const std::pair<const char*, OptionalNumber> centre[] = {{"cx", cx}, {"cy", cy}};
  for (const auto& [name, v] : centre)
    if (v && !std::isfinite(*v)) throw csgfit::InputError(std::string(name) + " must be finite");
  return {fx, fy, cx, cy, pixel_size, depth_unit};
}

NativeRangeResult run_range(std::vector<csgfit::RangeScan> scans,
                            std::vector<std::string> sources, const RangeSearch& search,
                            const py::object& progress, const CancelToken* cancel) {
  const csgfit::RangeFitOptions options = range_options(search);
  NativeRangeResult out;
  out.fit = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
    return csgfit::fit_range(scans, options, callback, flag);
  });
  out.sources = std::move(sources);
  if (scans.front().camera && scans.front().organised()) out.first_view = std::move(scans.front());
  return out;
}

py::array_t<int> int_array(const std::vector<int>& v) {
  py::array_t<int> out(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

void bind_result(py::module_& m) {
  py::class_<NativeRangeResult> c(m, "NativeRangeResult",
                                  "A range fit in model units; wrapped by csgfit.RangeFitResult.");
  def_cloud_outputs(c);
  c.def_property_readonly(
          "patch_of_point",
          [](const NativeRangeResult& r) { return int_array(r.fit.patch_of_point); },
          "Per merged point (views in order), its patch index; -1 = in no patch.")
      .def_property_readonly("has_preview",
                             [](const NativeRangeResult& r) { return r.first_view.has_value(); })
      .def(
          "to_json",
          [](const NativeRangeResult& r) { return csgfit::to_json_range(r.fit, r.sources); },
          "The range JSON document, as `csgfit range -o x.json` writes it.")
      .def(
          "report", [](const NativeRangeResult& r) { return csgfit::precedence_report(r.fit.graph); },
          "Seed 002's Fig. 10 listing of the precedence graph.")
      .def(
          "save_preview",
          [](const NativeRangeResult& r, const std::string& path) {
            if (!r.first_view)
              throw csgfit::InputError("no preview: the first input is not a range image with "
                                       "a camera");
            without_gil([&] { csgfit::write_range_preview(path, *r.first_view, r.fit); });
          },
          py::arg("path"), "Writes the segmentation / depth-error PNG (as --preview does).");
}

/// Defines a range fit: its input's arguments, then the search arguments every range fit
/// shares (with the CLI's defaults).
template <class Fit, class... InputArgs>
void def_range_fit(py::module_& m, const char* name, Fit&& fit, const char* doc,
                   InputArgs... input_args) {
  m.def(name, std::forward<Fit>(fit), input_args...,
        py::arg("primitives") = "box,sphere,cylinder,cone,torus", py::arg("time") = 20.0,
        py::arg("threads") = 0, py::arg("seed") = 1, py::arg("progress") = py::none(),
        py::arg("cancel") = nullptr, doc);
}

}  // namespace

void bind_range(py::module_& m) {
  bind_result(m);
  m.attr("FCSTD_WRITER") = CSGFIT_SOURCE_DIR "/freecad_workbench/csgfit_freecad/fcstd_writer.py";
  def_range_fit(
      m, "fit_range_files",
      [](const std::vector<std::string>& paths, OptionalNumber fx, OptionalNumber fy,
         OptionalNumber cx, OptionalNumber cy, OptionalNumber pixel_size,
         OptionalNumber depth_unit, const std::string& primitives, double time, int threads,
         std::uint64_t seed, const py::object& progress, const CancelToken* cancel) {
        if (paths.empty()) throw csgfit::InputError("no input given");
        csgfit::RangeReadOptions read;
        read.intrinsics = intrinsics(fx, fy, cx, cy, pixel_size, depth_unit);
        std::vector<csgfit::RangeScan> scans =
            without_gil([&] { return csgfit::read_ranges(paths, read); });
        return run_range(std::move(scans), paths, {primitives, time, threads, seed}, progress,
                         cancel);
      },
      "Fits a CSG tree to range images or point files of one part, as `csgfit range` does.",
      py::arg("paths"), py::arg("fx") = py::none(), py::arg("fy") = py::none(),
      py::arg("cx") = py::none(), py::arg("cy") = py::none(), py::arg("pixel_size") = py::none(),
      py::arg("depth_unit") = py::none());
  def_range_fit(
      m, "fit_point_arrays",
      [](const F64Array& points, const std::optional<F64Array>& normals,
         const std::string& source, const std::string& primitives, double time, int threads,
         std::uint64_t seed, const py::object& progress, const CancelToken* cancel) {
        csgfit::RangeScan scan;
        scan.source = source;
        scan.points = vec3s_from_array(points, "points");
        if (normals) {
          scan.normals = vec3s_from_array(*normals, "normals");
          if (scan.normals.size() != scan.points.size())
            throw csgfit::InputError("normals: " + std::to_string(scan.normals.size()) +
                                     " rows for " + std::to_string(scan.points.size()) +
                                     " points");
        }
        // Estimated where missing, kept (normalised) where given; bad ones are dropped.
        without_gil([&] { csgfit::complete_normals(scan); });
        std::vector<csgfit::RangeScan> scans;
        scans.push_back(std::move(scan));
        return run_range(std::move(scans), {source}, {primitives, time, threads, seed},
                         progress, cancel);
      },
      "Fits a CSG tree to unorganised points (n, 3), with normals (n, 3) or without.",
      py::arg("points"), py::arg("normals") = py::none(), py::arg("source") = "points");
}

}  // namespace csgfit_python
