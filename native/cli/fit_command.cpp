#include "fit_command.h"

#include <cstdio>

#include "option_checks.h"

namespace csgfit::cli {

void add_fit_args(CLI::App& command, FitArgs& args, const FitArgsHelp& help) {
  command.add_option("input", args.input, help.input)->required();
  command.add_option("-o,--output", args.output, help.output)->required();
  command.add_option("--time", args.time_limit, "time budget in seconds")
      ->check(obeys(option_rules::time));
  command.add_option("--seed", args.seed, "random seed: same seed and threads, same tree")
      ->check(seed_check());
  command.add_option("--threads", args.threads, "worker threads (0 = all cores)")
      ->check(obeys(option_rules::threads));
  command.add_option("--k", args.k, help.k)->check(obeys(option_rules::k));
  command.add_option("--primitives", args.primitives, help.primitives);
  command.add_option("--fn", args.fn, help.fn)->check(obeys(option_rules::fn));
  command.add_flag("-q,--quiet", args.quiet, help.quiet);
  command.add_flag("--no-optimize", args.no_optimize,
                   "skip the last stage, seed 001's tree optimiser (csgfit optimize)");
  add_memory_option(command);
}

void print_summary(const FitStats& stats) {
  std::fprintf(stderr,
               "csgfit: IoU %.4f, %zu primitives, %zu trees, %zu evaluations, %.2f s (%s)\n",
               stats.iou, stats.primitives, stats.trees, stats.evaluations, stats.seconds,
               stats.stop_reason.c_str());
}

}  // namespace csgfit::cli
