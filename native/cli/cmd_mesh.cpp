#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/input3d.h"
#include "csgfit/io/json.h"
#include "fit_command.h"
#include "option_checks.h"
#include "output.h"
#include "progress_bar.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

struct MeshArgs {
  FitArgs fit;
  int resolution = 0;
  bool no_align = false;
  bool no_construct = false;
};

void add_mesh_options(CLI::App& mesh, MeshArgs& a) {
  a.fit.time_limit = 30;
  a.fit.fn = 64;
  a.fit.primitives = kDefaultMeshPrimitives;
  add_fit_args(mesh, a.fit,
               {"STL, OBJ, OFF or PLY mesh, or .npy/.binvox voxel grid",
                "output: .scad, .json, .step or .FCStd",
                "size weight per primitive in voxels (default: 140 per million grid voxels)",
                "comma-separated: box,sphere,cylinder,cone,ellipsoid,torus,prism,rounded_box (the "
                "default: every one; all: every one but rounded_box)",
                "OpenSCAD $fn for round primitives", "no progress bar, warnings or summary"});
  mesh.add_option("--resolution", a.resolution,
                  "voxels along the longest side of a mesh's search grid (0 = auto: a coarse grid "
                  "of about half a million voxels for the search, then a polish on a fine grid of "
                  "about 11 voxels across the part's mean wall thickness)")
      ->check(obeys(option_rules::resolution));
  mesh.add_flag("--no-align", a.no_align,
                "fit along the mesh's own axes (default: along its dominant planar faces)");
  mesh.add_flag("--no-construct", a.no_construct,
                "search from voxels only (default: build the tree from the mesh's own faces "
                "first, and search only where they do not explain it)");
}

// `problems` gets the mesh's defects, for a warning once the fit succeeded; a fit that fails
// names them in its one-line error instead.
MeshFitResult read_and_fit(const MeshArgs& a, FitOptions3D options,
                           const ProgressCallback& progress, std::string* problems) {
  const auto read_start = std::chrono::steady_clock::now();
  const Input3D input = read_input3d(a.fit.input);
  *problems = input.warning();
  if (input.is_mesh()) {
    // --time is the whole run: reading the mesh and writing the result come out of it.
    const double spent =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    options.time_limit = std::max(0.05 * a.fit.time_limit, a.fit.time_limit - spent - 0.1);
  }
  MeshFitOptions mesh_options;
  mesh_options.resolution = a.resolution;
  mesh_options.align = !a.no_align;
  mesh_options.construct = !a.no_construct;
  try {
    return fit_input3d(input, options, mesh_options, progress);
  } catch (const InputError& e) {
    const std::string defects = problems->substr(0, problems->find(": inside/outside"));
    throw InputError(std::string(e.what()) + ": '" + a.fit.input + "'" +
                     (defects.empty() ? "" : ". " + defects));
  }
}

void run_mesh(const MeshArgs& a) {
  check_output(a.fit.output);
  const FitOptions3D options = fit_options<FitOptions3D>(a.fit);
  ProgressBar bar(!a.fit.quiet);
  std::string problems;
  const MeshFitResult fitted = read_and_fit(a, options, bar.callback(), &problems);
  bar.finish();
  if (!problems.empty() && !a.fit.quiet) std::cerr << "csgfit: warning: " << problems << "\n";

  const FitResult3D& result = fitted.fit;
  const VoxelGrid& grid = fitted.grid;  // the grid the summary's IoU is measured on
  Result3D out{result.tree, {}, {}};
  out.scad.fn = a.fit.fn;
  out.scad.source = fs::path(a.fit.input).filename().string();
  char summary[160];
  std::snprintf(summary, sizeof summary, "IoU %.4f on a %d x %d x %d grid of %g, %zu primitives",
                result.stats.iou, grid.nx(), grid.ny(), grid.nz(), grid.voxel_size(),
                result.stats.primitives);
  out.scad.summary = summary;
  out.document = [&] { return to_json3d(result, grid, out.scad.source, fitted.frame); };
  write_output(a.fit.output, out);
  if (!a.fit.quiet) print_summary(result.stats);
}

}  // namespace

Command add_mesh_command(CLI::App& app) {
  return make_command(app, "mesh", "fit a 3D CSG tree to a mesh or voxel grid", add_mesh_options,
                      run_mesh);
}

}  // namespace csgfit::cli
