// Option parsing and csgfit.InputError: the module's one-line answers to bad arguments.
#include "options.h"

#include <pybind11/pybind11.h>

#include <cmath>
#include <exception>
#include <stdexcept>

#include "bindings.h"
#include "csgfit/error.h"

namespace csgfit_python {

namespace py = pybind11;

namespace {

void check_search(const SearchArgs& args) {
  if (!std::isfinite(args.time) || args.time <= 0)
    throw csgfit::InputError("time must be a positive number of seconds");
  if (args.threads < 0) throw csgfit::InputError("threads must be >= 0 (0 = all cores)");
  if (!std::isfinite(args.k)) throw csgfit::InputError("k must be a finite number");
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

csgfit::MeshFitOptions mesh_fit_options(int resolution, double voxel_size) {
  if (resolution < 0 || resolution > 512)
    throw csgfit::InputError("resolution must be 0 (auto) .. 512");
  if (!std::isfinite(voxel_size) || voxel_size < 0)
    throw csgfit::InputError("voxel_size must be >= 0 (0 = from the resolution)");
  csgfit::MeshFitOptions options;
  options.resolution = resolution;
  options.voxel_size = voxel_size;
  return options;
}

void bind_errors(py::module_& m) {
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
