// Option parsing and csgfit.InputError: the module's one-line answers to bad arguments.
#include "options.h"

#include <pybind11/pybind11.h>

#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>

#include "bindings.h"
#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "csgfit/pipeline/option_limits.h"

namespace csgfit_python {

namespace py = pybind11;

namespace {

void check_search(const SearchArgs& args) {
  csgfit::check_option("time", args.time, csgfit::option_rules::time);
  csgfit::check_option("threads", args.threads, csgfit::option_rules::threads);
  if (args.k != -1) csgfit::check_option("k", args.k, csgfit::option_rules::k);  // -1: default
}

/// The parsers refuse unknown names with std::invalid_argument; `prefix` says which argument.
template <class Parse>
auto parsed(const char* prefix, Parse&& parse) {
  try {
    return parse();
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(prefix + std::string(e.what()));
  }
}

}  // namespace

void check_length(const char* name, double v, bool zero_ok) {
  if (std::isfinite(v) && (v > 0 || (zero_ok && v == 0))) return;
  throw csgfit::InputError(std::string(name) + (zero_ok ? " must be >= 0" : " must be > 0"));
}

csgfit::ImageReadOptions image_read_options(int threshold, bool invert, long long max_pixels,
                                            int max_size) {
  if (threshold > 255)
    throw csgfit::InputError("threshold must be a grey level 0..255, got " +
                             std::to_string(threshold));
  if (max_size < 0) throw csgfit::InputError("max_size must be >= 0");
  csgfit::ImageReadOptions options;
  options.threshold = threshold;
  options.invert = invert;
  if (max_pixels > 0) options.max_pixels = max_pixels;
  options.max_size = max_size;
  return options;
}

csgfit::FitOptions fit_options(const SearchArgs& args, int alternatives,
                               const std::string& quality) {
  check_search(args);
  if (alternatives < 0) throw csgfit::InputError("alternatives must be >= 0");
  csgfit::FitOptions options;
  options.k = args.k;
  options.primitives = parsed("", [&] { return csgfit::PrimitiveSet::parse(args.primitives); });
  if (options.primitives.empty()) throw csgfit::InputError("no primitive types selected");
  options.time_limit = args.time;
  options.threads = args.threads;
  options.seed = args.seed;
  options.alternatives = alternatives;
  // The quality levels (fast, default, best, paper) are the CLI's.
  options.search = parsed("", [&] { return csgfit::SearchParams::for_quality(quality); });
  return options;
}

csgfit::FitOptions3D fit_options_3d(const SearchArgs& args) {
  check_search(args);
  csgfit::FitOptions3D options;
  options.primitives =
      parsed("primitives: ", [&] { return csgfit::PrimitiveSet3D::parse(args.primitives); });
  options.k = args.k;
  options.time_limit = args.time;
  options.threads = args.threads;
  options.seed = args.seed;
  return options;
}

csgfit::MeshFitOptions mesh_fit_options(int resolution, double voxel_size, bool construct) {
  if (resolution < 0 || resolution > 512)
    throw csgfit::InputError("resolution must be 0 (auto) .. 512");
  if (!std::isfinite(voxel_size) || voxel_size < 0)
    throw csgfit::InputError("voxel_size must be >= 0 (0 = from the resolution)");
  csgfit::MeshFitOptions options;
  options.resolution = resolution;
  options.voxel_size = voxel_size;
  options.construct = construct;
  return options;
}

namespace {

// The rules by the names Python's argument checks use (csgfit/options.py).
const csgfit::NumberRule& rule_named(const std::string& name) {
  namespace r = csgfit::option_rules;
  static const std::pair<const char*, const csgfit::NumberRule*> rules[] = {
      {"time", &r::time},           {"threads", &r::threads},
      {"k", &r::k},                 {"fn", &r::fn},
      {"scale", &r::scale},         {"thickness", &r::thickness},
      {"resolution", &r::resolution}, {"image_side", &r::image_side},
      {"pixel_count", &r::pixel_count}, {"alternatives", &r::alternatives},
      {"threshold", &r::threshold}, {"focal_length", &r::focal_length},
      {"principal_point", &r::principal_point}, {"weight", &r::weight},
      {"inflate_steps", &r::inflate_steps}, {"frames", &r::frames},
      {"islands", &r::islands}, {"height", &r::height}};
  for (const auto& [key, rule] : rules)
    if (name == key) return *rule;
  throw std::logic_error("no option rule named " + name);
}

void bind_limits(py::module_& m) {
  m.attr("DEFAULT_MESH_PRIMITIVES") = csgfit::kDefaultMeshPrimitives;
  m.def("rule_violation",
        [](const std::string& rule, double value) {
          return csgfit::rule_violation(rule_named(rule), value);
        },
        py::arg("rule"), py::arg("value"),
        "Empty when value obeys the named option rule, else why not (one phrase).");
  m.def("check_allocation", &csgfit::check_allocation, py::arg("bytes"), py::arg("what"),
        "Raises InputError when `bytes` is over the memory budget.");
  m.def("set_max_memory",
        [](const std::string& size) {
          csgfit::set_memory_budget(
              static_cast<std::size_t>(csgfit::parse_memory_size("max_memory", size)));
        },
        py::arg("size"), "Sets the memory budget: '4G', '512M' or bytes; '0' is refused.");
  m.def("reset_max_memory", [] { csgfit::set_memory_budget(0); },
        "Restores the default memory budget (half of the machine's memory).");
  m.def("memory_budget", &csgfit::memory_budget, "The memory budget in force, in bytes.");
}

}  // namespace

void bind_errors(py::module_& m) {
  bind_limits(m);
  // Bad input is a ValueError for Python users; InputError keeps the solver's one-line message.
  static py::exception<csgfit::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const csgfit::InputError& e) {
      input_error(e.what());
    }
  });
}

}  // namespace csgfit_python
