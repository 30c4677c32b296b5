// What the two fitting commands (image and mesh) have in common: their shared options, the
// search options made of them, and the summary line after the fit.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "csgfit/error.h"
#include "csgfit/search/stats.h"

namespace csgfit::cli {

/// The shared options as parsed; a command sets its own defaults before registering them.
struct FitArgs {
  std::string input, output;
  double time_limit = 10;
  std::uint64_t seed = 1;
  int threads = 0;
  double k = -1;
  std::string primitives;
  int fn = 96;
  bool quiet = false;
  bool no_optimize = false;
};

/// The help texts that differ from one fitting command to the other.
struct FitArgsHelp {
  const char* input;
  const char* output;
  const char* k;
  const char* primitives;
  const char* fn;
  const char* quiet;
};

/// Registers the shared options on `command`, bound to `args`.
void add_fit_args(CLI::App& command, FitArgs& args, const FitArgsHelp& help);

/// The --primitives list as a PrimitiveSet or PrimitiveSet3D; InputError naming the bad item.
template <class Set>
Set primitive_set(const std::string& list) {
  try {
    return Set::parse(list);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--primitives: ") + e.what());
  }
}

/// The search options (FitOptions or FitOptions3D) that `args` asks for. Throws InputError for
/// a bad --primitives list.
template <class Options>
Options fit_options(const FitArgs& args) {
  Options options;
  options.primitives = primitive_set<decltype(options.primitives)>(args.primitives);
  options.k = args.k;
  options.time_limit = args.time_limit;
  options.threads = args.threads;
  options.seed = args.seed;
  options.optimize_tree = !args.no_optimize;
  return options;
}

/// The one line on stderr after a fit (unless --quiet).
void print_summary(const FitStats& stats);

}  // namespace csgfit::cli
