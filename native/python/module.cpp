// pybind11 bindings of the 2D and 3D fits: the native half of the `csgfit` Python package.
//
// The binding stays thin on purpose: it turns numpy arrays and files into Bitmaps, runs
// fit_bitmap with the GIL released, and hands trees back as plain dicts in pixel units (3D:
// meshes and voxel arrays into VoxelGrids, fit_voxels, the 3D JSON document as text). The
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

#include "csgfit/model/bitmap.h"
#include "csgfit/error.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/io/files.h"
#include "csgfit/io/image.h"
#include "csgfit/io/json.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/voxelize.h"
#include "csgfit/model/primitive2d.h"
#include "csgfit/model/tree2d.h"
#include "scad_writer.h"
#include "scad_writer3d.h"

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

// ---- 3D ------------------------------------------------------------------------------------

/// A 3D fit with the grid it was fitted on (the grid's placement maps voxels to model units).
struct NativeResult3D {
  csgfit::FitResult3D result;
  csgfit::VoxelGrid target;
  std::string source;
  std::string warning;  // what describe_mesh_problems said about the input mesh, if anything
};

using F64Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using I64Array = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// Voxel arrays larger than this are refused (the CLI's voxelisation limit).
constexpr std::size_t kMaxVoxels = std::size_t{1} << 27;

void check_grid_frame(const std::vector<double>& origin, double voxel_size) {
  if (origin.size() != 3) throw csgfit::InputError("origin must be three numbers (x, y, z)");
  for (double v : origin)
    if (!std::isfinite(v)) throw csgfit::InputError("origin must be finite");
  if (!std::isfinite(voxel_size) || voxel_size <= 0)
    throw csgfit::InputError("voxel_size must be a positive number");
}

/// Array index [i][j][k] is voxel (x, y, z) = (i, j, k), as in .npy files.
csgfit::VoxelGrid grid_from_array(const U8Array& voxels, const std::vector<double>& origin,
                                  double voxel_size) {
  if (voxels.ndim() != 3)
    throw csgfit::InputError("expected a 3D voxel array (nx x ny x nz), got " +
                             std::to_string(voxels.ndim()) + " dimension" +
                             (voxels.ndim() == 1 ? "" : "s"));
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
        if (v(i, j, k) != 0) grid.set(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k));
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

/// (n, 3) finite vertices and (m, 3) triangles indexing them.
csgfit::TriangleMesh mesh_from_arrays(const F64Array& vertices, const I64Array& triangles) {
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
  csgfit::TriangleMesh mesh;
  auto v = vertices.unchecked<2>();
  mesh.vertices.resize(static_cast<std::size_t>(vertices.shape(0)));
  for (py::ssize_t i = 0; i < vertices.shape(0); ++i) {
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(v(i, a)))
        throw csgfit::InputError("vertex " + std::to_string(i) + " is not finite");
      mesh.vertices[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] = v(i, a);
    }
  }
  auto t = triangles.unchecked<2>();
  mesh.triangles.resize(static_cast<std::size_t>(triangles.shape(0)));
  for (py::ssize_t i = 0; i < triangles.shape(0); ++i) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t idx = t(i, a);
      if (idx < 0 || idx >= vertices.shape(0))
        throw csgfit::InputError("triangle " + std::to_string(i) + " refers to vertex " +
                                 std::to_string(idx) + " (the mesh has " +
                                 std::to_string(vertices.shape(0)) + ")");
      mesh.triangles[static_cast<std::size_t>(i)][static_cast<std::size_t>(a)] =
          static_cast<int>(idx);
    }
  }
  return mesh;
}

/// Voxelises at `voxel_size` (> 0), `resolution` voxels along the longest side (> 0), or the
/// CLI's automatic size (both 0); `warning` gets the mesh diagnosis.
csgfit::VoxelGrid voxelize_mesh(const csgfit::TriangleMesh& mesh, int resolution,
                                double voxel_size, std::string* warning) {
  if (resolution < 0 || resolution > 512)
    throw csgfit::InputError("resolution must be 0 (auto) .. 512");
  if (!std::isfinite(voxel_size) || voxel_size < 0)
    throw csgfit::InputError("voxel_size must be >= 0 (0 = from the resolution)");
  const csgfit::MeshReport report = csgfit::analyze_mesh(mesh);
  if (warning) *warning = csgfit::describe_mesh_problems(report);
  csgfit::VoxelizeOptions options;
  options.resolution = resolution > 0 ? resolution : 96;
  options.voxel_size = voxel_size;
  if (voxel_size == 0 && resolution == 0) options.voxel_size = csgfit::auto_voxel_size(report);
  return csgfit::voxelize(mesh, options);
}

csgfit::FitOptions3D fit_options_3d(double k, const std::string& primitives, double time_limit,
                                    int threads, std::uint64_t seed, const py::object& progress) {
  if (!std::isfinite(time_limit) || time_limit <= 0)
    throw csgfit::InputError("time must be a positive number of seconds");
  if (threads < 0) throw csgfit::InputError("threads must be >= 0 (0 = all cores)");
  if (!std::isfinite(k)) throw csgfit::InputError("k must be a finite number");
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw csgfit::InputError("progress must be callable or None");
  csgfit::FitOptions3D options;
  try {
    options.primitives = csgfit::PrimitiveSet3D::parse(primitives);
  } catch (const std::invalid_argument& e) {
    throw csgfit::InputError(std::string("primitives: ") + e.what());
  }
  if (!options.primitives.has(csgfit::PrimitiveKind3D::Box))
    throw csgfit::InputError("primitives: the 3D fit needs boxes among them");
  options.k = k;
  options.time_limit = time_limit;
  options.threads = threads;
  options.seed = seed;
  return options;
}

NativeResult3D run_fit3d(const csgfit::VoxelGrid& target, double k,
                         const std::string& primitives, double time_limit, int threads,
                         std::uint64_t seed, const py::object& progress,
                         const CancelToken* cancel, const std::string& source,
                         const std::string& warning) {
  const csgfit::FitOptions3D options = fit_options_3d(k, primitives, time_limit, threads, seed, progress);
  if (target.count() == 0) throw csgfit::InputError("no solid found (no voxel is set)");
  NativeResult3D out;
  out.target = target;
  out.source = source;
  out.warning = warning;
  const std::atomic<bool>* flag = cancel ? cancel->flag() : nullptr;
  ProgressBridge bridge(progress, flag);
  {
    py::gil_scoped_release release;
    try {
      out.result = csgfit::fit_voxels(
          out.target, options, [&bridge](const csgfit::FitProgress& p) { return bridge(p); },
          flag);
    } catch (const std::invalid_argument& e) {
      throw csgfit::InputError(e.what());
    }
  }
  bridge.rethrow_if_failed();
  return out;
}

/// A mesh fit as `csgfit mesh` does it (fitting frame, coarse search, fine polish, surface
/// refinement); the preview grid is the mesh voxelised in its own axes at the fit's voxel size.
NativeResult3D run_fit_mesh(const csgfit::TriangleMesh& mesh, int resolution, double k,
                            const std::string& primitives, double time_limit, int threads,
                            std::uint64_t seed, const py::object& progress,
                            const CancelToken* cancel, const std::string& source) {
  if (resolution < 0 || resolution > 512)
    throw csgfit::InputError("resolution must be 0 (auto) .. 512");
  const csgfit::FitOptions3D options = fit_options_3d(k, primitives, time_limit, threads, seed, progress);
  csgfit::MeshFitOptions mesh_options;
  mesh_options.resolution = resolution;
  NativeResult3D out;
  out.source = source;
  const std::atomic<bool>* flag = cancel ? cancel->flag() : nullptr;
  ProgressBridge bridge(progress, flag);
  {
    py::gil_scoped_release release;
    try {
      csgfit::MeshFitResult fitted = csgfit::fit_mesh(
          mesh, options, mesh_options,
          [&bridge](const csgfit::FitProgress& p) { return bridge(p); }, flag);
      out.warning = csgfit::describe_mesh_problems(fitted.report);
      out.result = std::move(fitted.fit);
      if (fitted.frame.is_identity()) {
        out.target = std::move(fitted.grid);
      } else {
        csgfit::VoxelizeOptions v;
        v.voxel_size = fitted.grid.voxel_size();
        out.target = csgfit::voxelize(mesh, v);
      }
    } catch (const std::invalid_argument& e) {
      throw csgfit::InputError(e.what());
    }
  }
  bridge.rethrow_if_failed();
  return out;
}

}  // namespace

PYBIND11_MODULE(_csgfit, m) {
  m.doc() =
      "Native core of the csgfit package: bitmap, mesh and voxel to CSG tree fitting. Use the "
      "`csgfit` package (csgfit.fit_image, csgfit.fit_mesh, csgfit.fit_voxels) rather than this "
      "module directly.";

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
  py::class_<NativeResult3D>(m, "NativeResult3D",
                             "A 3D fit in model units with its voxel grid; wrapped by "
                             "csgfit.FitResult3D.")
      .def_property_readonly("source", [](const NativeResult3D& r) { return r.source; })
      .def_property_readonly("warning", [](const NativeResult3D& r) { return r.warning; },
                             "What is wrong with the input mesh ('' when nothing).")
      .def_property_readonly("shape", [](const NativeResult3D& r) {
        return py::make_tuple(r.target.nx(), r.target.ny(), r.target.nz());
      }, "Grid size (nx, ny, nz).")
      .def_property_readonly("origin", [](const NativeResult3D& r) {
        return py::make_tuple(r.target.origin_x(), r.target.origin_y(), r.target.origin_z());
      }, "Model coordinates of the grid's corner (voxel (0, 0, 0)'s low corner).")
      .def_property_readonly("voxel_size", [](const NativeResult3D& r) {
        return r.target.voxel_size();
      }, "Voxel edge in model units.")
      .def("to_json", [](const NativeResult3D& r) {
        return csgfit::to_json3d(r.result, r.target, r.source);
      }, "The 3D JSON document (docs/JSON_SCHEMA.md, 3D documents).")
      .def("target", [](const NativeResult3D& r) { return array_from_grid(r.target); },
           "The fitted voxels: bool array [i, j, k] = voxel (x, y, z).")
      .def("raster", [](const NativeResult3D& r) {
        csgfit::VoxelGrid grid;
        {
          py::gil_scoped_release release;
          grid = csgfit::render(r.result.tree, r.target);
        }
        return array_from_grid(grid);
      }, "The solver's voxels of the tree on the same grid (bool array [i, j, k]).")
      .def("to_scad", [](const NativeResult3D& r, int fn) {
        if (fn < 3) throw csgfit::InputError("fn must be >= 3");
        csgfit::ScadOptions3D options;
        options.fn = fn;
        options.source = r.source;
        return csgfit::to_scad(r.result.tree, options);
      }, py::arg("fn") = 64, "OpenSCAD 2021.01 source of the tree (model units).");

  m.def(
      "load_mesh",
      [](const std::string& path) {
        csgfit::TriangleMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = csgfit::read_mesh(path);
        }
        py::array_t<double> vertices({static_cast<py::ssize_t>(mesh.vertices.size()),
                                      static_cast<py::ssize_t>(3)});
        py::array_t<std::int32_t> triangles({static_cast<py::ssize_t>(mesh.triangles.size()),
                                             static_cast<py::ssize_t>(3)});
        auto v = vertices.mutable_unchecked<2>();
        auto t = triangles.mutable_unchecked<2>();
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
          for (int a = 0; a < 3; ++a) v(static_cast<py::ssize_t>(i), a) = mesh.vertices[i][a];
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
          for (int a = 0; a < 3; ++a) t(static_cast<py::ssize_t>(i), a) = mesh.triangles[i][a];
        return py::make_tuple(vertices, triangles);
      },
      py::arg("path"), "Reads an STL, OBJ, OFF or PLY mesh: (vertices (n, 3), triangles (m, 3)).");

  m.def(
      "load_voxels",
      [](const std::string& path) {
        csgfit::VoxelGrid grid;
        {
          py::gil_scoped_release release;
          grid = csgfit::read_voxels(path);
        }
        return grid_tuple(grid);
      },
      py::arg("path"), "Reads a .npy or .binvox voxel grid: (bool array, origin, voxel_size).");

  m.def("is_mesh_path", &csgfit::is_mesh_path, py::arg("path"));
  m.def("is_voxel_path", &csgfit::is_voxel_path, py::arg("path"));

  m.def(
      "voxelize",
      [](const F64Array& vertices, const I64Array& triangles, int resolution, double voxel_size) {
        const csgfit::TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        std::string warning;
        csgfit::VoxelGrid grid;
        {
          py::gil_scoped_release release;
          grid = voxelize_mesh(mesh, resolution, voxel_size, &warning);
        }
        py::tuple t = grid_tuple(grid);
        return py::make_tuple(t[0], t[1], t[2], warning);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("resolution") = 0,
      py::arg("voxel_size") = 0.0,
      "Solid voxels of a mesh as the CLI makes them: (bool array, origin, voxel_size, warning).");

  m.def(
      "fit_mesh_arrays",
      [](const F64Array& vertices, const I64Array& triangles, int resolution, double voxel_size,
         double k, const std::string& primitives, double time_limit, int threads,
         std::uint64_t seed, const py::object& progress, const CancelToken* cancel,
         const std::string& source) {
        const csgfit::TriangleMesh mesh = mesh_from_arrays(vertices, triangles);
        if (voxel_size == 0)
          return run_fit_mesh(mesh, resolution, k, primitives, time_limit, threads, seed,
                              progress, cancel, source);
        // An explicit voxel size: the fit runs on exactly that grid, in the mesh's axes.
        std::string warning;
        csgfit::VoxelGrid grid;
        {
          py::gil_scoped_release release;
          grid = voxelize_mesh(mesh, resolution, voxel_size, &warning);
        }
        return run_fit3d(grid, k, primitives, time_limit, threads, seed, progress, cancel,
                         source, warning);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("resolution") = 0,
      py::arg("voxel_size") = 0.0, py::arg("k") = -1.0, py::arg("primitives") = "box,sphere,cylinder,cone,ellipsoid,prism",
      py::arg("time") = 30.0, py::arg("threads") = 0, py::arg("seed") = 1,
      py::arg("progress") = py::none(), py::arg("cancel") = nullptr, py::arg("source") = "",
      "Voxelises a mesh and fits a 3D CSG tree to it (GIL released while solving).");

  m.def(
      "fit_voxels",
      [](const U8Array& voxels, const std::vector<double>& origin, double voxel_size, double k,
         const std::string& primitives, double time_limit, int threads, std::uint64_t seed,
         const py::object& progress, const CancelToken* cancel, const std::string& source) {
        const csgfit::VoxelGrid grid = grid_from_array(voxels, origin, voxel_size);
        return run_fit3d(grid, k, primitives, time_limit, threads, seed, progress, cancel,
                         source, "");
      },
      py::arg("voxels"), py::arg("origin") = std::vector<double>{0, 0, 0},
      py::arg("voxel_size") = 1.0, py::arg("k") = -1.0, py::arg("primitives") = "box,sphere,cylinder,cone,ellipsoid,prism",
      py::arg("time") = 30.0, py::arg("threads") = 0, py::arg("seed") = 1,
      py::arg("progress") = py::none(), py::arg("cancel") = nullptr, py::arg("source") = "",
      "Fits a 3D CSG tree to a voxel array ([i, j, k] = voxel (x, y, z), nonzero = solid).");
}
