// The point-cloud fit (seed 004): point files and arrays go through fit_points, the one place
// where its stages are ordered, so Python fits exactly as `csgfit points` does.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

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
#include "csgfit/io/range_read.h"
#include "csgfit/pipeline/fit_points.h"
#include "progress.h"
#include "tree_outputs.h"

namespace csgfit_python {

namespace {

struct NativePointsResult {
  csgfit::PointsFitResult fit;
  std::vector<std::string> sources;
};

/// The arguments of a points fit, with the CLI's defaults; checked as the CLI checks its own.
struct PointsSearch {
  std::string scan = "auto", search = "gp", primitives;
  double floor = 0, time = 30;
  int islands = 4, threads = 0;
  std::uint64_t seed = 1;
};

csgfit::PointsFitOptions points_options(const PointsSearch& s) {
  if (!std::isfinite(s.time) || s.time <= 0)
    throw csgfit::InputError("time must be a positive number of seconds");
  if (s.threads < 0) throw csgfit::InputError("threads must be >= 0 (0 = all cores)");
  if (s.islands < 1 || s.islands > 64) throw csgfit::InputError("islands must be 1 .. 64");
  if (!std::isfinite(s.floor)) throw csgfit::InputError("floor must be finite");
  if (s.scan != "auto" && s.scan != "top" && s.scan != "all")
    throw csgfit::InputError("scan must be 'top', 'all' or 'auto', got '" + s.scan + "'");
  if (s.search != "gp" && s.search != "hill")
    throw csgfit::InputError("search must be 'gp' or 'hill', got '" + s.search + "'");
  csgfit::PointsFitOptions o;
  try {
    o.primitives = csgfit::PrimitiveSet3D::parse(s.primitives);
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(std::string("primitives: ") + e.what());
  }
  if (o.primitives.empty()) throw csgfit::InputError("no primitive types selected");
  if (s.scan != "auto") o.scan = s.scan == "top" ? csgfit::ScanKind::Top : csgfit::ScanKind::All;
  o.search = s.search == "hill" ? csgfit::PointSearch::Hill : csgfit::PointSearch::Gp;
  o.floor = s.floor;
  o.time_limit = s.time;
  o.islands = static_cast<std::size_t>(s.islands);
  o.threads = s.threads;
  o.seed = s.seed;
  return o;
}

NativePointsResult run_points(const std::vector<csgfit::RangeScan>& scans,
                              std::vector<std::string> sources, const PointsSearch& search,
                              const py::object& progress, const CancelToken* cancel) {
  const csgfit::PointsFitOptions options = points_options(search);
  NativePointsResult out;
  out.fit = run_fit_released(progress, cancel, [&](const auto& callback, const auto* flag) {
    return csgfit::fit_points(scans, options, callback, flag);
  });
  out.sources = std::move(sources);
  return out;
}

void bind_result(py::module_& m) {
  py::class_<NativePointsResult> c(m, "NativePointsResult",
                                   "A points fit in model units; wrapped by csgfit.PointsFitResult.");
  def_cloud_outputs(c);
  c.def(
          "to_json",
          [](const NativePointsResult& r) { return csgfit::to_json_points(r.fit, r.sources); },
          "The points JSON document, as `csgfit points -o x.json` writes it.")
      .def(
          "report", [](const NativePointsResult& r) { return csgfit::fitness_report(r.fit); },
          "Seed 004's fitness terms, as `csgfit points --report` prints them.");
}

/// Defines a points fit: its input's arguments, then the search arguments (the CLI's defaults).
template <class Fit, class... InputArgs>
void def_points_fit(py::module_& m, const char* name, Fit&& fit, const char* doc,
                    InputArgs... input_args) {
  m.def(name, std::forward<Fit>(fit), input_args..., py::arg("scan") = "auto",
        py::arg("floor") = 0.0, py::arg("search") = "gp", py::arg("islands") = 4,
        py::arg("primitives") = "box,sphere,cylinder,nurbs", py::arg("time") = 30.0,
        py::arg("threads") = 0, py::arg("seed") = 1, py::arg("progress") = py::none(),
        py::arg("cancel") = nullptr, doc);
}

}  // namespace

void bind_points(py::module_& m) {
  bind_result(m);
  def_points_fit(
      m, "fit_points_files",
      [](const std::vector<std::string>& paths, const std::string& scan, double floor,
         const std::string& search, int islands, const std::string& primitives, double time,
         int threads, std::uint64_t seed, const py::object& progress, const CancelToken* cancel) {
        if (paths.empty()) throw csgfit::InputError("no input given");
        csgfit::RangeReadOptions read;
        read.strict_points = true;
        const std::vector<csgfit::RangeScan> scans =
            without_gil([&] { return csgfit::read_ranges(paths, read); });
        return run_points(scans, paths, {scan, search, primitives, floor, time, islands, threads, seed},
                          progress, cancel);
      },
      "Fits a CSG tree with NURBS terminals to point files of one part, as `csgfit points` does.",
      py::arg("paths"));
  def_points_fit(
      m, "fit_points_cloud",
      [](const F64Array& points, const std::optional<F64Array>& normals, const std::string& source,
         const std::string& scan, double floor, const std::string& search, int islands,
         const std::string& primitives, double time, int threads, std::uint64_t seed,
         const py::object& progress, const CancelToken* cancel) {
        csgfit::RangeScan cloud;
        cloud.source = source;
        cloud.points = vec3s_from_array(points, "points");
        if (normals) {
          // Kept as given: a zero normal is an error the fit names, not a point to drop.
          cloud.normals = vec3s_from_array(*normals, "normals");
          if (cloud.normals.size() != cloud.points.size())
            throw csgfit::InputError("normals: " + std::to_string(cloud.normals.size()) +
                                     " rows for " + std::to_string(cloud.points.size()) + " points");
        } else {
          without_gil([&] { csgfit::complete_normals(cloud); });
        }
        return run_points({cloud}, {source}, {scan, search, primitives, floor, time, islands, threads, seed},
                          progress, cancel);
      },
      "Fits a CSG tree with NURBS terminals to points (n, 3), with normals (n, 3) or without.",
      py::arg("points"), py::arg("normals") = py::none(), py::arg("source") = "points");
}

}  // namespace csgfit_python
