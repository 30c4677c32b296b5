// csgfit range: range images or point clouds of one part to a CSG tree (seed 002).
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "csgfit/io/range_preview.h"
#include "csgfit/io/range_read.h"
#include "csgfit/pipeline/fit_range.h"
#include "option_checks.h"
#include "output.h"
#include "progress_bar.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

struct RangeArgs {
  std::vector<std::string> inputs;
  std::string output, preview;
  double time_limit = 20;
  std::uint64_t seed = 1;
  int threads = 0, fn = 96;
  std::string primitives = "box,sphere,cylinder,cone,torus";
  bool quiet = false, report = false;
  std::optional<double> fx, fy, cx, cy, pixel_size, depth_unit;
  long long max_size = 4096;
};

void add_range_options(CLI::App& range, RangeArgs& a) {
  range.add_option("inputs", a.inputs,
                   "range images (16-bit PNG or .npy depth with a .json sidecar), organised clouds "
                   "(.npy H x W x 3, PLY with width/height) or points (.xyz, .ply); several views "
                   "of one part are merged")
      ->required();
  range.add_option("-o,--output", a.output, "output: .scad, .json, .step or .FCStd")->required();
  range.add_option("--time", a.time_limit, "time budget in seconds")
      ->check(obeys(option_rules::time));
  range.add_option("--seed", a.seed, "random seed (RANSAC and refinement): same seed, same tree")
      ->check(seed_check());
  range.add_option("--threads", a.threads, "worker threads (0 = all cores)")
      ->check(obeys(option_rules::threads));
  range.add_option("--primitives", a.primitives,
                   "comma-separated: box,sphere,cylinder,cone,torus (or all)");
  range.add_option("--fn", a.fn, "OpenSCAD $fn for round primitives")->check(obeys(option_rules::fn));
  range.add_flag("-q,--quiet", a.quiet, "no progress bar or summary");
  range.add_flag("--report", a.report,
                 "print the precedence graph as seed 002's Fig. 10 lists it (subobjects, orders, "
                 "primitives with axes, sizes and sign)");
  range.add_option("--preview", a.preview,
                   "PNG: the first view segmented by patch beside the result's depth error");
  range.add_option("--fx", a.fx, "pinhole focal length in pixels (x) when there is no sidecar")
      ->check(obeys(option_rules::focal_length));
  range.add_option("--fy", a.fy, "pinhole focal length in pixels (y)")
      ->check(obeys(option_rules::focal_length));
  range.add_option("--cx", a.cx, "principal point, pixels (default: the image centre)")
      ->check(obeys(option_rules::principal_point));
  range.add_option("--cy", a.cy, "principal point, pixels")
      ->check(obeys(option_rules::principal_point));
  range.add_option("--pixel-size", a.pixel_size, "orthographic pixel size in model units")
      ->check(obeys(option_rules::scale));
  range.add_option("--depth-unit", a.depth_unit, "model units per 16-bit PNG step (default 1)")
      ->check(obeys(option_rules::scale));
  range.add_option("--max-size", a.max_size, "refuse images with a side longer than this")
      ->check(obeys(option_rules::image_side));
  add_memory_option(range);
}

RangeReadOptions read_options(const RangeArgs& a) {
  RangeReadOptions o;
  o.intrinsics = {a.fx, a.fy, a.cx, a.cy, a.pixel_size, a.depth_unit};
  o.max_pixels = a.max_size * a.max_size;
  return o;
}

void run_range(const RangeArgs& a) {
  check_output(a.output);
  if (!a.preview.empty()) check_png_output(a.preview, "--preview");
  RangeFitOptions options;
  try {
    options.primitives = PrimitiveSet3D::parse(a.primitives);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--primitives: ") + e.what());
  }
  options.time_limit = a.time_limit;
  options.seed = a.seed;
  options.threads = a.threads;
  const std::vector<RangeScan> scans = read_ranges(a.inputs, read_options(a));
  if (!a.preview.empty() && !(scans.front().camera && scans.front().organised()))
    throw InputError("--preview needs a range image with a camera as the first input");
  ProgressBar bar(!a.quiet);
  const RangeFitResult fitted = fit_range(scans, options, bar.callback());
  bar.finish();

  Result3D out{fitted.tree, {}, {}};
  out.scad.fn = a.fn;
  out.scad.source = fs::path(a.inputs.front()).filename().string();
  char summary[200];
  std::snprintf(summary, sizeof summary, "%zu primitives in %d subobjects from %zu surface patches",
                fitted.stats.primitives, fitted.graph.subobjects, fitted.patches.size());
  if (!fitted.views.empty())  // points without a camera have no silhouette to compare
    std::snprintf(summary + std::strlen(summary), sizeof summary - std::strlen(summary),
                  "; silhouette IoU %.4f", fitted.stats.iou);
  out.scad.summary = summary;
  out.document = [&] { return to_json_range(fitted, a.inputs); };
  write_output(a.output, out);
  if (!a.preview.empty()) write_range_preview(a.preview, scans.front(), fitted);
  if (a.report) std::cout << precedence_report(fitted.graph);
  if (!a.quiet) {
    std::fprintf(stderr, "csgfit: %s", summary);
    for (const ViewAgreement& v : fitted.views)
      std::fprintf(stderr, "; %s: depth error %.3g (%.2f %% of the diagonal)",
                   fs::path(v.source).filename().string().c_str(), v.depth_error,
                   100 * v.depth_error / fitted.diagonal);
    std::fprintf(stderr, "; %.2f s\n", fitted.stats.seconds);
  }
}

}  // namespace

Command add_range_command(CLI::App& app) {
  return make_command(app, "range", "fit a 3D CSG tree to range images or point clouds (seed 002)",
                      add_range_options, run_range);
}

}  // namespace csgfit::cli
