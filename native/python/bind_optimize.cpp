// Seed 001's optimiser on an OpenSCAD program (a .scad or .csg path, or .csg text).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/io/openscad_program.h"
#include "csgfit/optimise/optimize_tree.h"
#include "options.h"
#include "progress.h"

namespace csgfit_python {
namespace {

py::dict report_dict(const csgfit::opt::OptimizeReport& r) {
  py::dict d;
  d["size_before"] = r.size_before;
  d["size_after"] = r.size_after;
  d["proximity_before"] = r.proximity_before;
  d["proximity_after"] = r.proximity_after;
  d["opaque"] = r.opaque;
  d["dominant_halfspaces"] = r.dominant_halfspaces;
  d["remaining_solids"] = r.remaining_solids;
  d["check_points"] = r.check_points;
  d["check_mismatches"] = r.check_mismatches;
  d["reverted"] = r.reverted;
  d["seconds"] = r.seconds;
  py::list stages, front;
  for (const auto& [name, size] : r.stage_sizes) stages.append(py::make_tuple(name, size));
  for (const auto& p : r.pareto) front.append(py::make_tuple(p.size, p.proximity));
  d["stages"] = stages;
  d["pareto"] = front;
  return d;
}

py::dict optimize_program(const std::string& source, bool is_path, const std::string& method,
                          double proximity_weight, double time, std::uint64_t seed) {
  csgfit::opt::OptimizeOptions o;
  o.method = csgfit::opt::remaining_method_from_string(method);
  o.proximity_weight = proximity_weight;
  o.time_limit = time;
  o.seed = seed;
  struct Done {
    std::string scad, csg;
    std::size_t before = 0, after = 0;
    csgfit::opt::OptimizeReport report;
  };
  const Done done = without_gil([&] {
    const csgfit::ScadProgram p =
        is_path ? csgfit::read_openscad_program(source)
                : csgfit::program_from_csg(csgfit::parse_openscad_csg(source, "<text>"), source, "<text>");
    const auto r = p.dimension == 3 ? csgfit::opt::optimize_tree(p.tree, p.halfspaces3, o)
                                    : csgfit::opt::optimize_tree(p.tree, p.halfspaces2, o);
    csgfit::ScadWriteOptions readable, flat;
    flat.csg_style = true;
    return Done{csgfit::write_openscad_program(p, r.tree, readable), csgfit::write_openscad_program(p, r.tree, flat),
                csgfit::opt::literal_count(p.tree), csgfit::opt::literal_count(r.tree), r.report};
  });
  py::dict out;
  out["scad"] = done.scad;
  out["csg"] = done.csg;
  out["primitives_before"] = done.before;
  out["primitives_after"] = done.after;
  out["report"] = report_dict(done.report);
  return out;
}

}  // namespace

void bind_optimize(py::module_& m) {
  m.def("optimize_program", &optimize_program, py::arg("source"), py::arg("is_path"), py::arg("method"),
        py::arg("proximity_weight"), py::arg("time"), py::arg("seed"),
        "Seed 001's optimiser on a .scad / .csg path or .csg text: scad, csg, report.");
}

}  // namespace csgfit_python
