// pybind11 bindings of the 2D fit: the native half of the `csgfit` Python package.
//
// The binding stays thin on purpose: it turns numpy arrays and files into Bitmaps, runs
// fit_bitmap with the GIL released, and hands trees back as plain dicts in pixel units. The
// Python package (csgfit/__init__.py) turns those into model-unit objects, so the user-facing
// API can evolve without recompiling.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include "csgfit/bitmap.h"
#include "csgfit/error.h"
#include "csgfit/fit.h"
#include "csgfit/image_io.h"
#include "csgfit/json_io.h"
#include "csgfit/primitive.h"
#include "csgfit/tree.h"
#include "scad_writer.h"

namespace py = pybind11;

namespace {

/// A flag another Python thread sets to stop a running fit. Shared ownership so that the
/// solver's view of it outlives any Python-side juggling of the token object.
class CancelToken {
 public:
  void cancel() { flag_->store(true); }
  void reset() { flag_->store(false); }
  bool cancelled() const { return flag_->load(); }
  const std::atomic<bool>* flag() const { return flag_.get(); }

 private:
  std::shared_ptr<std::atomic<bool>> flag_ = std::make_shared<std::atomic<bool>>(false);
};

/// A fit (or a loaded JSON file) with the frame that maps it to model units and, when known,
/// the target bitmap it was fitted to.
struct NativeResult {
  csgfit::FitResult result;
  csgfit::ModelFrame frame;
  csgfit::Bitmap target;  // empty for results read from JSON
};

using U8Array = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

void check_2d(const py::array& a) {
  if (a.ndim() != 2) {
    throw csgfit::InputError("expected a 2D array (height x width), got " +
                             std::to_string(a.ndim()) + " dimension" +
                             (a.ndim() == 1 ? "" : "s"));
  }
  if (a.shape(0) == 0 || a.shape(1) == 0) {
    throw csgfit::InputError("empty image (" + std::to_string(a.shape(1)) + " x " +
                             std::to_string(a.shape(0)) + " pixels)");
  }
  if (a.shape(0) > 1 << 20 || a.shape(1) > 1 << 20) {
    throw csgfit::InputError("image too large (" + std::to_string(a.shape(1)) + " x " +
                             std::to_string(a.shape(0)) + " pixels)");
  }
}

csgfit::Bitmap bitmap_from_mask(const U8Array& mask) {
  check_2d(mask);
  const int h = static_cast<int>(mask.shape(0));
  const int w = static_cast<int>(mask.shape(1));
  csgfit::Bitmap bitmap(w, h);
  auto v = mask.unchecked<2>();
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      if (v(row, col) != 0) bitmap.set(col, row);
    }
  }
  return bitmap;
}

py::array_t<bool> mask_from_bitmap(const csgfit::Bitmap& bitmap) {
  const py::ssize_t h = bitmap.height();
  const py::ssize_t w = bitmap.width();
  py::array_t<bool> out({h, w});
  auto v = out.mutable_unchecked<2>();
  for (int row = 0; row < bitmap.height(); ++row) {
    for (int col = 0; col < bitmap.width(); ++col) v(row, col) = bitmap.get(col, row);
  }
  return out;
}

csgfit::ImageReadOptions read_options(int threshold, bool invert, long long max_pixels,
                                      int max_size) {
  if (threshold > 255) {
    throw csgfit::InputError("threshold must be a grey level 0..255, got " +
                             std::to_string(threshold));
  }
  if (max_size < 0) throw csgfit::InputError("max_size must be >= 0");
  csgfit::ImageReadOptions options;
  options.threshold = threshold;
  options.invert = invert;
  if (max_pixels > 0) options.max_pixels = max_pixels;
  options.max_size = max_size;
  return options;
}

/// Search settings per quality level (fast, default, best, paper), as the CLI's.
csgfit::SearchParams search_params(const std::string& quality) {
  try {
    return csgfit::SearchParams::for_quality(quality);
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(e.what());
  }
}

csgfit::FitOptions fit_options(double k, const std::string& primitives, double time_limit,
                               int threads, std::uint64_t seed, int alternatives,
                               const std::string& quality) {
  if (!std::isfinite(time_limit) || time_limit <= 0) {
    throw csgfit::InputError("time must be a positive number of seconds");
  }
  if (threads < 0) throw csgfit::InputError("threads must be >= 0 (0 = all cores)");
  if (alternatives < 0) throw csgfit::InputError("alternatives must be >= 0");
  if (!std::isfinite(k)) throw csgfit::InputError("k must be a finite number");
  csgfit::FitOptions options;
  options.k = k;
  try {
    options.primitives = csgfit::PrimitiveSet::parse(primitives);
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(e.what());
  }
  if (options.primitives.empty()) throw csgfit::InputError("no primitive types selected");
  options.time_limit = time_limit;
  options.threads = threads;
  options.seed = seed;
  options.alternatives = alternatives;
  options.search = search_params(quality);
  return options;
}

py::dict node_to_dict(const csgfit::Node& node) {
  py::dict d;
  if (node.is_leaf()) {
    const csgfit::Primitive& p = node.primitive;
    d["type"] = std::string(csgfit::to_string(p.kind));
    d["cx"] = p.cx;
    d["cy"] = p.cy;
    d["w"] = p.w;
    d["h"] = p.h;
    d["angle"] = p.angle;
    d["apex"] = p.apex;
    return d;
  }
  d["op"] = std::string(csgfit::to_string(node.kind));
  py::list children;
  for (const csgfit::Node& child : node.children) children.append(node_to_dict(child));
  d["children"] = children;
  return d;
}

py::dict stats_to_dict(const csgfit::FitStats& s) {
  py::dict d;
  d["k"] = s.k;
  d["score"] = s.score;
  d["excess"] = s.excess;
  d["uncovered"] = s.uncovered;
  d["primitives"] = s.primitives;
  d["iou"] = s.iou;
  d["evaluations"] = s.evaluations;
  d["trees"] = s.trees;
  d["seconds"] = s.seconds;
  d["stop_reason"] = s.stop_reason;
  return d;
}

/// index -1 is the best tree, 0..n-1 the alternatives.
const csgfit::Node& tree_at(const NativeResult& r, int index, const csgfit::FitStats** stats) {
  if (index == -1) {
    if (stats) *stats = &r.result.stats;
    return r.result.tree;
  }
  if (index < 0 || static_cast<std::size_t>(index) >= r.result.alternatives.size()) {
    throw py::index_error("no alternative " + std::to_string(index) + " (this result has " +
                          std::to_string(r.result.alternatives.size()) + ")");
  }
  const csgfit::FitTree& alt = r.result.alternatives[static_cast<std::size_t>(index)];
  if (stats) *stats = &alt.stats;
  return alt.tree;
}

/// Bridges the solver's progress reports to a Python callable. The solver may call from any
/// of its threads; the GIL is taken only for the Python call, and calls are throttled so that
/// a fast search is not slowed down by the interpreter.
class ProgressBridge {
 public:
  ProgressBridge(py::object callback, const std::atomic<bool>* cancel)
      : callback_(std::move(callback)), cancel_(cancel) {}

  bool operator()(const csgfit::FitProgress& progress) {
    if (stop_.load() || (cancel_ && cancel_->load())) return false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto now = std::chrono::steady_clock::now();
      if (now - last_ < std::chrono::milliseconds(50) && progress.fraction < 1.0) return true;
      last_ = now;
    }
    py::gil_scoped_acquire gil;
    try {
      // Lets Ctrl-C stop a fit run from the main thread (a no-op on other threads).
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!callback_.is_none()) {
        py::object answer = callback_(progress);
        if (answer.ptr() == Py_False) stop_.store(true);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
      stop_.store(true);
    }
    return !stop_.load();
  }

  /// Re-raises an exception the callback raised (call with the GIL held).
  void rethrow_if_failed() {
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  bool stopped() const { return stop_.load(); }

 private:
  py::object callback_;
  const std::atomic<bool>* cancel_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
  std::exception_ptr error_;
};

NativeResult run_fit(const U8Array& mask, double k, const std::string& primitives,
                     double time_limit, int threads, std::uint64_t seed, int alternatives,
                     const std::string& quality, const py::object& progress,
                     const CancelToken* cancel, double pixel_size, double thickness,
                     const std::string& source) {
  if (!std::isfinite(pixel_size) || pixel_size <= 0) {
    throw csgfit::InputError("pixel_size must be a positive number");
  }
  if (!std::isfinite(thickness) || thickness < 0) {
    throw csgfit::InputError("thickness must be >= 0");
  }
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw csgfit::InputError("progress must be callable or None");
  }
  NativeResult out;
  out.target = bitmap_from_mask(mask);
  out.frame.pixel_size = pixel_size;
  out.frame.thickness = thickness;
  out.frame.source = source;
  const csgfit::FitOptions options =
      fit_options(k, primitives, time_limit, threads, seed, alternatives, quality);

  // The token's own flag is what the solver polls; a False from the callback stops the
  // search through the callback's return value.
  const std::atomic<bool>* flag = cancel ? cancel->flag() : nullptr;
  ProgressBridge bridge(progress, flag);
  {
    py::gil_scoped_release release;
    out.result = csgfit::fit_bitmap(
        out.target, options, [&bridge](const csgfit::FitProgress& p) { return bridge(p); },
        flag);
  }
  bridge.rethrow_if_failed();
  return out;
}

}  // namespace

PYBIND11_MODULE(_csgfit, m) {
  m.doc() =
      "Native core of the csgfit package: bitmap to CSG tree fitting. Use the `csgfit` package "
      "(csgfit.fit_image) rather than this module directly.";

  // Bad input is a ValueError for Python users; InputError keeps the solver's one-line message.
  static py::exception<csgfit::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const csgfit::InputError& e) {
      input_error(e.what());
    }
  });

  py::class_<CancelToken>(m, "CancelToken",
                          "A flag to stop a running fit from another thread.\n\n"
                          "Pass it as fit_image(..., cancel=token) and call token.cancel() from "
                          "any thread: the fit returns promptly with the best tree found so "
                          "far and stats.stop_reason == 'cancelled'.")
      .def(py::init<>())
      .def("cancel", &CancelToken::cancel, "Ask the fit to stop (thread-safe).")
      .def("reset", &CancelToken::reset, "Clear the flag so the token can be reused.")
      .def_property_readonly("cancelled", &CancelToken::cancelled,
                             "Whether cancel() was called (and not reset since).");

  py::class_<csgfit::FitProgress>(m, "FitProgress",
                                  "A progress report passed to the progress callback.")
      .def_readonly("fraction", &csgfit::FitProgress::fraction,
                    "0..1 of the time budget or of convergence, whichever is ahead.")
      .def_readonly("best_score", &csgfit::FitProgress::best_score,
                    "Score of the best tree so far (lower is better).")
      .def_readonly("best_primitives", &csgfit::FitProgress::best_primitives,
                    "Primitives in the best tree so far.")
      .def_readonly("evaluations", &csgfit::FitProgress::evaluations,
                    "Tree evaluations so far.")
      .def_readonly("seconds", &csgfit::FitProgress::seconds, "Wall time so far.")
      .def("__repr__", [](const csgfit::FitProgress& p) {
        return "FitProgress(fraction=" + std::to_string(p.fraction) +
               ", best_score=" + std::to_string(p.best_score) +
               ", best_primitives=" + std::to_string(p.best_primitives) + ")";
      });

  py::class_<NativeResult>(m, "NativeResult",
                           "A fitted (or loaded) result in the solver's pixel units; wrapped by "
                           "csgfit.FitResult.")
      .def_property_readonly("width", [](const NativeResult& r) { return r.result.width; },
                             "Canvas width in pixels.")
      .def_property_readonly("height", [](const NativeResult& r) { return r.result.height; },
                             "Canvas height in pixels.")
      .def_property(
          "pixel_size", [](const NativeResult& r) { return r.frame.pixel_size; },
          [](NativeResult& r, double v) {
            if (!std::isfinite(v) || v <= 0) throw csgfit::InputError("pixel_size must be > 0");
            r.frame.pixel_size = v;
          },
          "Model units (mm) per pixel.")
      .def_property(
          "thickness", [](const NativeResult& r) { return r.frame.thickness; },
          [](NativeResult& r, double v) {
            if (!std::isfinite(v) || v < 0) throw csgfit::InputError("thickness must be >= 0");
            r.frame.thickness = v;
          },
          "Extrusion height in model units (0 = a 2D result).")
      .def_property_readonly("source", [](const NativeResult& r) { return r.frame.source; },
                             "Input file name (empty for arrays).")
      .def_property_readonly(
          "alternative_count",
          [](const NativeResult& r) { return r.result.alternatives.size(); },
          "Number of alternative trees.")
      .def("tree", [](const NativeResult& r, int index) { return node_to_dict(tree_at(r, index, nullptr)); },
           py::arg("index") = -1,
           "Tree as nested dicts in pixel units (index -1 = best, 0.. = alternatives).")
      .def(
          "stats",
          [](const NativeResult& r, int index) {
            const csgfit::FitStats* s = nullptr;
            tree_at(r, index, &s);
            return stats_to_dict(*s);
          },
          py::arg("index") = -1, "Stats of a tree as a dict.")
      .def(
          "raster",
          [](const NativeResult& r, int index) {
            const csgfit::Node& tree = tree_at(r, index, nullptr);
            csgfit::Bitmap raster;
            {
              py::gil_scoped_release release;
              raster = csgfit::render(tree, r.result.width, r.result.height);
            }
            return mask_from_bitmap(raster);
          },
          py::arg("index") = -1,
          "The solver's raster of a tree: bool array (height, width), row 0 at the top.")
      .def(
          "target",
          [](const NativeResult& r) -> py::object {
            if (r.target.empty()) return py::none();
            return mask_from_bitmap(r.target);
          },
          "The bitmap that was fitted (bool array, True = shape), or None for loaded JSON.")
      .def(
          "to_json", [](const NativeResult& r) { return csgfit::to_json(r.result, r.frame); },
          "JSON text (schema in docs/JSON_SCHEMA.md) of the result and its alternatives.")
      .def(
          "to_scad",
          [](const NativeResult& r, int index, int fn) {
            if (fn < 3) throw csgfit::InputError("fn must be >= 3");
            const csgfit::FitStats* s = nullptr;
            const csgfit::Node& tree = tree_at(r, index, &s);
            csgfit::ScadOptions options;
            options.fn = fn;
            return csgfit::to_scad(tree, r.frame, options, s);
          },
          py::arg("index") = -1, py::arg("fn") = 96,
          "OpenSCAD 2021.01 source of a tree in model units.");

  m.def(
      "load_bitmap",
      [](const std::string& path, int threshold, bool invert, long long max_pixels,
         int max_size) {
        const csgfit::ImageReadOptions options =
            read_options(threshold, invert, max_pixels, max_size);
        csgfit::Bitmap bitmap;
        {
          py::gil_scoped_release release;
          bitmap = csgfit::read_bitmap(path, options);
        }
        return mask_from_bitmap(bitmap);
      },
      py::arg("path"), py::arg("threshold") = -1, py::arg("invert") = false,
      py::arg("max_pixels") = 0, py::arg("max_size") = 0,
      "Reads an image file and thresholds it like the CLI: bool array, True = shape.");

  m.def(
      "threshold_grey",
      [](const U8Array& grey, int threshold, bool invert) {
        check_2d(grey);
        csgfit::GreyImage image;
        image.height = static_cast<int>(grey.shape(0));
        image.width = static_cast<int>(grey.shape(1));
        image.grey.assign(grey.data(), grey.data() + grey.size());
        return mask_from_bitmap(
            csgfit::threshold_image(image, read_options(threshold, invert, 0, 0)));
      },
      py::arg("grey"), py::arg("threshold") = -1, py::arg("invert") = false,
      "Thresholds a uint8 grey array (dark = shape unless invert; threshold -1 = Otsu).");

  m.def("fit", &run_fit, py::arg("mask"), py::arg("k") = -1.0, py::arg("primitives") = "all",
        py::arg("time") = 10.0, py::arg("threads") = 0, py::arg("seed") = 1,
        py::arg("alternatives") = 0, py::arg("quality") = "default",
        py::arg("progress") = py::none(), py::arg("cancel") = nullptr,
        py::arg("pixel_size") = 1.0, py::arg("thickness") = 0.0, py::arg("source") = "",
        "Fits a CSG tree to a mask (2D uint8/bool array, nonzero = shape). Releases the GIL "
        "while solving; progress(FitProgress) may return False to cancel.");

  m.def(
      "from_json",
      [](const std::string& text) {
        NativeResult r;
        r.result = csgfit::from_json(text, &r.frame);
        return r;
      },
      py::arg("text"), "Parses JSON written by to_json into a NativeResult.");

  m.def("default_k", &csgfit::default_k, py::arg("width"), py::arg("height"),
        "Size weight k used when none is given: 25 at 128 x 128, scaled to the pixel count.");
}
