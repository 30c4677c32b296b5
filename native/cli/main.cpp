// The `csgfit` command line.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "csgfit/error.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_voxels.h"
#include "csgfit/io/files.h"
#include "csgfit/io/image.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/json.h"
#include "csgfit/pipeline/fit_mesh.h"
#include "csgfit/io/mesh_read.h"
#include "csgfit/io/voxels_read.h"
#include "csgfit/model/mesh.h"
#include "csgfit/model/voxelize.h"
#include "fcstd_writer.h"
#include "progress_bar.h"
#include "scad_writer.h"
#include "scad_writer3d.h"
#include "step_writer.h"

namespace fs = std::filesystem;
using namespace csgfit;
using cli::ProgressBar;
using cli::write_fcstd;

namespace {

enum class OutputFormat { Scad, Json, FCStd, Step };

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

OutputFormat output_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".scad") return OutputFormat::Scad;
  if (ext == ".json") return OutputFormat::Json;
  if (ext == ".fcstd") return OutputFormat::FCStd;
  if (is_step_path(path)) return OutputFormat::Step;
  throw InputError("unknown output format '" + (ext.empty() ? path : ext) +
                   "' (expected .scad, .json, .FCStd or .step)");
}

// Fails before a long fit rather than after it.
void check_writable(const std::string& path) {
  const fs::path parent = fs::absolute(fs::path(path)).parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw InputError("cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
  if (access(parent.c_str(), W_OK) != 0)
    throw InputError("cannot write '" + path + "': " + std::strerror(errno));
  if (fs::is_directory(fs::path(path), ec)) throw InputError("cannot write '" + path + "': it is a folder");
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string alternative_path(const std::string& out, std::size_t i) {
  fs::path p(out);
  return (p.parent_path() / (p.stem().string() + ".alt" + std::to_string(i) + p.extension().string()))
      .string();
}

void write_result(const FitResult& result, const ModelFrame& frame, const std::string& out,
                  int fn) {
  ScadOptions scad;
  scad.fn = fn;
  scad.width_px = result.width;
  scad.height_px = result.height;
  switch (output_format(out)) {
    case OutputFormat::Scad: {
      write_file_atomic(out, to_scad(result.tree, frame, scad, &result.stats));
      for (std::size_t i = 0; i < result.alternatives.size(); ++i)
        write_file_atomic(alternative_path(out, i + 1),
                          to_scad(result.alternatives[i].tree, frame, scad,
                                  &result.alternatives[i].stats));
      break;
    }
    case OutputFormat::Json: write_file_atomic(out, to_json(result, frame)); break;
    case OutputFormat::FCStd: write_fcstd(to_json(result, frame), out); break;
    case OutputFormat::Step: {
      write_step(result.tree, frame, out);
      for (std::size_t i = 0; i < result.alternatives.size(); ++i)
        write_step(result.alternatives[i].tree, frame, alternative_path(out, i + 1));
      break;
    }
  }
}

// A 3D document (csgfit mesh -o .json) to .scad or .step; fn = 0 means the mesh command's 64.
void export_3d(const std::string& json_text, const std::string& out, int fn) {
  std::string source;
  const Node3D tree = from_json3d(json_text, &source);
  const OutputFormat format = output_format(out);
  if (format == OutputFormat::Scad) {
    ScadOptions3D scad;
    if (fn > 0) scad.fn = fn;
    scad.source = source;
    write_file_atomic(out, to_scad(tree, scad));
  } else if (format == OutputFormat::Step) {
    StepOptions step;
    step.source = source;
    write_step(tree, out, step);
  } else {
    throw InputError("cannot write '" + out + "': a 3D result exports to .scad or .step");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"csgfit: turn bitmaps into compact, editable CSG trees (OpenSCAD, JSON, FreeCAD)"};
  app.set_version_flag("--version", std::string("csgfit ") + CSGFIT_VERSION);
  app.require_subcommand(1);

  // csgfit image
  std::string in, out, preview, raster, primitives = "all", quality = "default", preset = "default";
  double time_limit = 10, k = -1, pixel_size = 1, thickness = 0;
  int threads = 0, threshold = -1, alternatives = 0, max_size = 0, fn = 96;
  long long max_pixels = 4096LL * 4096LL;
  std::uint64_t seed = 1;
  bool invert = false, quiet = false;
  CLI::App* image = app.add_subcommand("image", "fit a CSG tree to a bitmap");
  image->add_option("input", in, "PNG, JPEG, BMP, PGM/PBM or TGA image")->required();
  image->add_option("-o,--output", out, "output: .scad, .json, .FCStd or .step")->required();
  image->add_option("--time", time_limit, "time budget in seconds")->check(CLI::PositiveNumber);
  image->add_option("--seed", seed, "random seed: same seed and threads, same tree");
  image->add_option("--threads", threads, "worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  image->add_option("--quality", quality, "fast, default or best")
      ->check(CLI::IsMember({"fast", "default", "best"}));
  image->add_option("--preset", preset, "search parameters: default or paper (seed 000, Table 2)")
      ->check(CLI::IsMember({"default", "paper"}));
  image->add_option("--k", k, "size weight per primitive (default: 25 at 128 x 128, scaled to the area)")
      ->check(CLI::NonNegativeNumber);
  image->add_option("--primitives", primitives, "comma-separated: rectangle,circle,ellipse,triangle (or all)");
  image->add_option("--alternatives", alternatives, "also write up to N structurally different trees")
      ->check(CLI::Range(0, 20));
  image->add_option("--threshold", threshold, "grey level 0-255 (default: Otsu)")->check(CLI::Range(0, 255));
  image->add_flag("--invert", invert, "light pixels are the shape");
  image->add_option("--pixel-size", pixel_size, "millimetres per pixel")->check(CLI::PositiveNumber);
  image->add_option("--thickness", thickness, "extrude the 2D result to this height (mm)")
      ->check(CLI::NonNegativeNumber);
  image->add_option("--max-size", max_size, "downsample images larger than N pixels on a side")
      ->check(CLI::PositiveNumber);
  image->add_option("--max-pixels", max_pixels, "refuse images with more pixels than this")
      ->check(CLI::PositiveNumber);
  image->add_option("--preview", preview, "PNG of input and result overlaid (excess red, uncovered blue)");
  image->add_option("--raster", raster, "PNG of the solver's own raster of the result");
  image->add_option("--fn", fn, "OpenSCAD $fn for circles and ellipses")->check(CLI::Range(3, 1000));
  image->add_flag("-q,--quiet", quiet, "no progress bar and no summary");

  // csgfit export: a saved JSON result to another format
  std::string ex_in, ex_out;
  CLI::App* exporter = app.add_subcommand("export", "convert a csgfit .json result to .scad, .json, .FCStd or .step");
  exporter->add_option("input", ex_in, "csgfit .json result")->required();
  exporter->add_option("-o,--output", ex_out, "output: .scad, .json, .FCStd or .step")->required();
  exporter->add_option("--fn", fn, "OpenSCAD $fn")->check(CLI::Range(3, 1000));

  // csgfit render: the solver's raster of a saved result
  std::string rd_in, rd_out;
  CLI::App* renderer = app.add_subcommand("render", "draw a csgfit .json result as the solver rasterises it");
  renderer->add_option("input", rd_in, "csgfit .json result")->required();
  renderer->add_option("-o,--output", rd_out, "PNG")->required();

  // csgfit mesh: a triangle mesh or voxel grid to a 3D CSG tree
  std::string mesh_in, mesh_out, mesh_primitives = "box,sphere,cylinder,cone,ellipsoid,prism";
  double mesh_time = 30, mesh_k = -1;
  int mesh_resolution = 0, mesh_threads = 0, mesh_fn = 64;
  std::uint64_t mesh_seed = 1;
  bool mesh_quiet = false, mesh_no_align = false;
  CLI::App* mesher = app.add_subcommand("mesh", "fit a 3D CSG tree to a mesh or voxel grid");
  mesher->add_option("input", mesh_in, "STL, OBJ, OFF or PLY mesh, or .npy/.binvox voxel grid")->required();
  mesher->add_option("-o,--output", mesh_out, "output: .scad, .json, .step or .FCStd")->required();
  mesher->add_option("--resolution", mesh_resolution,
                     "voxels along the longest side of a mesh's search grid (0 = auto: a coarse grid "
                     "of about half a million voxels for the search, then a polish on a fine grid of "
                     "about 11 voxels across the part's mean wall thickness)")
      ->check(CLI::Range(0, 512));
  mesher->add_option("--time", mesh_time, "time budget in seconds")->check(CLI::PositiveNumber);
  mesher->add_option("--seed", mesh_seed, "random seed: same seed and threads, same tree");
  mesher->add_option("--threads", mesh_threads, "worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  mesher->add_option("--k", mesh_k, "size weight per primitive in voxels (default: 200 per million grid voxels)")
      ->check(CLI::NonNegativeNumber);
  mesher->add_option("--primitives", mesh_primitives,
                     "comma-separated: box,sphere,cylinder,cone,ellipsoid,torus,prism (or all)");
  mesher->add_option("--fn", mesh_fn, "OpenSCAD $fn for round primitives")->check(CLI::Range(3, 1000));
  mesher->add_flag("--no-align", mesh_no_align,
                   "fit along the mesh's own axes (default: along its dominant planar faces)");
  mesher->add_flag("-q,--quiet", mesh_quiet, "no progress bar, warnings or summary");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    std::cerr << "csgfit: " << msg << " (see csgfit --help)\n";
    return 2;
  }

  try {
    if (*exporter) {
      output_format(ex_out);
      check_writable(ex_out);
      const std::string text = read_text_file(ex_in);
      if (is_json3d(text)) {
        export_3d(text, ex_out, exporter->count("--fn") ? fn : 0);
        return 0;
      }
      ModelFrame frame;
      FitResult result = from_json(text, &frame);
      write_result(result, frame, ex_out, fn);
      return 0;
    }
    if (*mesher) {
      const std::string ext = lower_extension(mesh_out);
      if (ext != ".scad" && ext != ".json" && ext != ".fcstd" && !is_step_path(mesh_out))
        throw InputError("unknown output format '" + (ext.empty() ? mesh_out : ext) +
                         "' for a mesh (expected .scad, .json, .step or .FCStd)");
      check_writable(mesh_out);
      FitOptions3D options;
      try {
        options.primitives = PrimitiveSet3D::parse(mesh_primitives);
      } catch (const std::invalid_argument& e) {
        throw InputError(std::string("--primitives: ") + e.what());
      }
      options.k = mesh_k;
      options.time_limit = mesh_time;
      options.threads = mesh_threads;
      options.seed = mesh_seed;
      ProgressBar bar(!mesh_quiet);
      auto on_progress = [&](const FitProgress& p) { return bar.update(p); };
      const auto read_start = std::chrono::steady_clock::now();
      const Input3D input = read_input3d(mesh_in);
      const std::string problems = input.warning();
      if (!problems.empty() && !mesh_quiet) std::cerr << "csgfit: warning: " << problems << "\n";
      if (input.is_mesh()) {
        // --time is the whole run: reading the mesh and writing the result come out of it.
        const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
        options.time_limit = std::max(0.05 * mesh_time, mesh_time - spent - 0.1);
      }
      MeshFitOptions mopt;
      mopt.resolution = mesh_resolution;
      mopt.align = !mesh_no_align;
      MeshFitResult fitted;
      try {
        fitted = fit_input3d(input, options, mopt, on_progress);
      } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + ": '" + mesh_in + "'");
      }
      const FitResult3D& result = fitted.fit;
      const VoxelGrid& target = fitted.grid;  // the grid the summary's IoU is measured on
      const Quaternion& frame = fitted.frame;
      bar.finish();
      const std::string source = fs::path(mesh_in).filename().string();
      if (ext == ".scad") {
        ScadOptions3D scad;
        scad.fn = mesh_fn;
        scad.source = source;
        char summary[160];
        std::snprintf(summary, sizeof summary, "IoU %.4f on a %d x %d x %d grid of %g, %zu primitives",
                      result.stats.iou, target.nx(), target.ny(), target.nz(), target.voxel_size(),
                      result.stats.primitives);
        scad.summary = summary;
        write_file_atomic(mesh_out, to_scad(result.tree, scad));
      } else if (ext == ".fcstd") {
        write_fcstd(to_json3d(result, target, source, frame), mesh_out);
      } else if (is_step_path(mesh_out)) {
        StepOptions step;
        step.source = source;
        write_step(result.tree, mesh_out, step);
      } else {
        write_file_atomic(mesh_out, to_json3d(result, target, source, frame));
      }
      if (!mesh_quiet)
        std::fprintf(stderr, "csgfit: IoU %.4f, %zu primitives, %zu trees, %zu evaluations, %.2f s (%s)\n",
                     result.stats.iou, result.stats.primitives, result.stats.trees,
                     result.stats.evaluations, result.stats.seconds, result.stats.stop_reason.c_str());
      return 0;
    }
    if (*renderer) {
      check_writable(rd_out);
      FitResult result = from_json(read_text_file(rd_in));
      const Bitmap r = render(result.tree, result.width, result.height);
      write_bitmap_png(rd_out, r);
      return 0;
    }

    // Found out before the fit, not after it.
    if (output_format(out) == OutputFormat::Step && !(thickness > 0))
      throw InputError("cannot write '" + out + "': STEP needs a thickness (give --thickness)");
    check_writable(out);
    if (!preview.empty()) check_writable(preview);
    if (!raster.empty()) check_writable(raster);
    FitOptions options;
    try {
      options.primitives = PrimitiveSet::parse(primitives);
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("--primitives: ") + e.what());
    }
    options.k = k;
    options.time_limit = time_limit;
    options.threads = threads;
    options.seed = seed;
    options.alternatives = alternatives;
    options.search = SearchParams::for_quality(preset == "paper" ? preset : quality);

    ImageReadOptions read;
    read.threshold = threshold;
    read.invert = invert;
    read.max_size = max_size;
    read.max_pixels = max_pixels;
    const Bitmap target = read_bitmap(in, read);
    if (target.count() == 0)
      throw InputError("no shape found in '" + in + "' (all pixels are background; try --invert or --threshold)");

    ProgressBar bar(!quiet);
    FitResult result = fit_bitmap(target, options, [&](const FitProgress& p) { return bar.update(p); });
    bar.finish();

    ModelFrame frame;
    frame.pixel_size = pixel_size;
    frame.thickness = thickness;
    frame.source = fs::path(in).filename().string();
    write_result(result, frame, out, fn);
    const Bitmap fitted = render(result.tree, result.width, result.height);
    if (!preview.empty()) write_preview_png(preview, target, fitted, target.width() < 256 ? 4 : 1);
    if (!raster.empty()) write_bitmap_png(raster, fitted);
    if (!quiet) {
      std::fprintf(stderr, "csgfit: IoU %.4f, %zu primitives, %zu trees, %zu evaluations, %.2f s (%s)\n",
                   result.stats.iou, result.stats.primitives, result.stats.trees,
                   result.stats.evaluations, result.stats.seconds, result.stats.stop_reason.c_str());
    }
    return 0;
  } catch (const InputError& e) {
    std::cerr << "csgfit: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "csgfit: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "csgfit: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "csgfit: internal error: " << e.what() << "\n";
    return 1;
  }
}
