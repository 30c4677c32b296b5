// csgfit optimize: a CSG tree (OpenSCAD .scad or .csg, or our .json) to a smaller tree of the
// same solid, by seed 001's pipeline.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/json.h"
#include "csgfit/io/openscad_program.h"
#include "csgfit/optimise/tree_expression.h"
#include "optimize_output.h"
#include "option_checks.h"

namespace csgfit::cli {
namespace {

struct OptimizeArgs {
  std::string input, output, method = "auto";
  double proximity_weight = 2, time_limit = 10;
  std::uint64_t seed = 1;
  bool report = false, no_decompose = false, quiet = false;
};

void add_optimize_options(CLI::App& c, OptimizeArgs& a) {
  c.add_option("input", a.input, "CSG tree: .scad (run through OpenSCAD), .csg or csgfit .json")->required();
  c.add_option("-o,--output", a.output, "output: .scad, .csg, .json, .FCStd or .step")->required();
  c.add_option("--method", a.method, "remaining-solid optimiser: auto, espresso, qmc, setcover, ga")
      ->capture_default_str();
  c.add_option("--proximity-weight", a.proximity_weight, "the GA's proximity weight (seed: 2)")
      ->check(obeys(option_rules::weight))->capture_default_str();
  c.add_option("--time", a.time_limit, "seconds at most for the GA and the exact set cover")
      ->check(obeys(option_rules::time))->capture_default_str();
  c.add_option("--seed", a.seed, "random seed (samples, GA, annealer)")->check(seed_check());
  c.add_flag("--report", a.report, "print what each stage removed");
  c.add_flag("--no-decompose", a.no_decompose, "skip the decomposition by dominant halfspaces");
  c.add_flag("-q,--quiet", a.quiet, "no summary line");
  add_memory_option(c);
}

opt::OptimizeOptions options_of(const OptimizeArgs& a) {
  opt::OptimizeOptions o;
  o.method = opt::remaining_method_from_string(a.method);
  o.proximity_weight = a.proximity_weight;
  o.time_limit = a.time_limit;
  o.seed = a.seed;
  o.decompose = !a.no_decompose;
  return o;
}

void print_report(const opt::OptimizeReport& r) {
  std::printf("size %zu", r.size_before);
  for (const auto& [stage, size] : r.stage_sizes) std::printf(" -> %zu (%s)", size, stage.c_str());
  std::printf("\nrules: %zu structural rewrites, %zu operands removed by empty-set decisions (%zu decisions, %zu cached)\n",
              r.structural_rewrites, r.sampled_removals, r.empty_decisions, r.cache_hits);
  std::printf("decomposition: %zu dominant halfspaces, %zu remaining solids, %zu made smaller\n",
              r.dominant_halfspaces, r.remaining_solids, r.remaining_improved);
  for (const auto& p : r.pareto) std::printf("pareto: size %zu proximity %.3f\n", p.size, p.proximity);
  std::printf("check: %zu fresh samples, %zu disagree%s\n", r.check_points, r.check_mismatches,
              r.reverted ? " (reverted to the input)" : "");
}

void print_summary(const opt::OptimizeReport& r, std::size_t prims_before, std::size_t prims_after) {
  std::fprintf(stderr,
               "csgfit: size %zu -> %zu, %zu -> %zu primitives, proximity %.3f -> %.3f%s, %.2f s\n",
               r.size_before, r.size_after, prims_before, prims_after, r.proximity_before, r.proximity_after,
               r.opaque ? (", " + std::to_string(r.opaque) + " opaque kept").c_str() : "", r.seconds);
}

void run_optimize(const OptimizeArgs& a) {
  const opt::OptimizeOptions options = options_of(a);
  const OptimizedTree result = optimize_file(a.input, a.output, options);
  if (a.report) print_report(result.report);
  if (!a.quiet) print_summary(result.report, result.primitives_before, result.primitives_after);
}

}  // namespace

Command add_optimize_command(CLI::App& app) {
  return make_command(app, "optimize", "a CSG tree (.scad, .csg, .json) to a smaller tree of the same solid",
                      add_optimize_options, run_optimize);
}

}  // namespace csgfit::cli
