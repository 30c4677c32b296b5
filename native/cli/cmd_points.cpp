// csgfit points: a scanned point cloud to a CSG tree with NURBS terminals (seed 004).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "csgfit/io/range_read.h"
#include "csgfit/pipeline/fit_points.h"
#include "option_checks.h"
#include "output.h"
#include "progress_bar.h"

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

struct PointsArgs {
  std::vector<std::string> inputs;
  std::vector<std::string> outputs;
  double time_limit = 30, floor = 0;
  std::uint64_t seed = 1;
  int threads = 0, fn = 96;
  std::size_t islands = 4;
  std::string primitives = "box,sphere,cylinder,nurbs", scan = "auto", search = "gp";
  bool quiet = false, report = false;
};

void add_points_options(CLI::App& cmd, PointsArgs& a) {
  cmd.add_option("inputs", a.inputs,
                 "points (.xyz: x y z [nx ny nz] a line; .ply, ASCII or binary, with or without "
                 "normals); several scans of one part are merged")
      ->required();
  cmd.add_option("-o,--output", a.outputs,
                 "output: .scad, .json, .step or .FCStd; repeat -o for several from one fit")
      ->required();
  cmd.add_option("--time", a.time_limit, "time budget in seconds")->check(obeys(option_rules::time));
  cmd.add_option("--seed", a.seed, "random seed: same seed, same tree (when the search ends by generations)")
      ->check(seed_check());
  cmd.add_option("--threads", a.threads, "worker threads (0 = all cores)")
      ->check(obeys(option_rules::threads));
  cmd.add_option("--primitives", a.primitives,
                 "comma-separated: box,sphere,cylinder,cone,ellipsoid,torus,prism,rounded_box,nurbs");
  cmd.add_option("--scan", a.scan, "top (seen from above: 2.5D), all (all around) or auto")
      ->check(CLI::IsMember({"top", "all", "auto"}));
  cmd.add_option("--floor", a.floor, "top scans: the height of the table the part stands on")
      ->check(obeys(option_rules::height));
  cmd.add_option("--search", a.search, "gp (seed 004's GP/ES on islands) or hill (the voxel hill climbing)")
      ->check(CLI::IsMember({"gp", "hill"}));
  cmd.add_option("--islands", a.islands, "GP populations (1 = one population)")
      ->check(obeys(option_rules::islands));
  cmd.add_option("--fn", a.fn, "OpenSCAD $fn for round primitives")->check(obeys(option_rules::fn));
  cmd.add_flag("-q,--quiet", a.quiet, "no progress bar or summary");
  cmd.add_flag("--report", a.report, "print seed 004's fitness terms of the result");
  add_memory_option(cmd);
}

PointsFitOptions fit_options(const PointsArgs& a) {
  PointsFitOptions o;
  try {
    o.primitives = PrimitiveSet3D::parse(a.primitives);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--primitives: ") + e.what());
  }
  o.time_limit = a.time_limit;
  o.seed = a.seed;
  o.threads = a.threads;
  o.floor = a.floor;
  o.islands = a.islands;
  o.search = a.search == "hill" ? PointSearch::Hill : PointSearch::Gp;
  if (a.scan != "auto") o.scan = a.scan == "top" ? ScanKind::Top : ScanKind::All;
  return o;
}

void run_points(const PointsArgs& a) {
  for (const std::string& out : a.outputs) check_output(out);
  const PointsFitOptions options = fit_options(a);
  for (const std::string& in : a.inputs) {
    const std::string ext = fs::path(in).extension().string();
    if (ext != ".xyz" && ext != ".ply" && ext != ".XYZ" && ext != ".PLY")
      throw InputError("'" + in + "': csgfit points reads .xyz or .ply (range images: csgfit range)");
  }
  RangeReadOptions read;
  read.strict_points = true;
  const std::vector<RangeScan> scans = read_ranges(a.inputs, read);
  ProgressBar bar(!a.quiet);
  const PointsFitResult fitted = fit_points(scans, options, bar.callback());
  bar.finish();

  Result3D out{fitted.tree, {}, {}};
  out.scad.fn = a.fn;
  out.scad.source = fs::path(a.inputs.front()).filename().string();
  char summary[200];
  std::snprintf(summary, sizeof summary, "%zu primitives, scan %s, %s, fitness %.4f, mean distance %.3g",
                fitted.stats.primitives, fitted.scan == ScanKind::Top ? "top" : "all",
                fitted.islands ? "GP/ES" : "hill climbing", fitted.terms.fitness,
                fitted.terms.mean_distance);
  out.scad.summary = summary;
  out.document = [&] { return to_json_points(fitted, a.inputs); };
  for (const std::string& path : a.outputs) write_output(path, out);
  if (a.report) std::fputs(fitness_report(fitted).c_str(), stdout);
  if (!a.quiet) std::fprintf(stderr, "csgfit: %s; %.2f s\n", summary, fitted.stats.seconds);
}

}  // namespace

Command add_points_command(CLI::App& app) {
  return make_command(app, "points", "fit a CSG tree with NURBS terminals to a scanned point cloud (seed 004)",
                      add_points_options, run_points);
}

}  // namespace csgfit::cli
