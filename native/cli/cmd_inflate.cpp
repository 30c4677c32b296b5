// csgfit inflate: seed 001's redundancy generator on an OpenSCAD program: the same solid from
// a larger tree, for testing and benchmarking the optimiser.
#include <cstdio>
#include <sstream>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/openscad_program.h"
#include "csgfit/optimise/inflate.h"
#include "option_checks.h"

namespace csgfit::cli {
namespace {

struct InflateArgs {
  std::string input, output, strategies = "csi,dni,dli,ali";
  std::size_t steps = 10;
  std::uint64_t seed = 1;
  bool quiet = false;
};

void add_inflate_options(CLI::App& c, InflateArgs& a) {
  c.add_option("input", a.input, "OpenSCAD program: .scad (run through OpenSCAD) or .csg")->required();
  c.add_option("-o,--output", a.output, "output: .scad or .csg")->required();
  c.add_option("--steps", a.steps, "insertions (seed 001: 10)")->check(obeys(option_rules::inflate_steps))
      ->capture_default_str();
  c.add_option("--strategies", a.strategies, "comma-separated, equally likely: csi, dni, dli, ali")
      ->capture_default_str();
  c.add_option("--seed", a.seed, "random seed")->check(seed_check());
  c.add_flag("-q,--quiet", a.quiet, "no summary line");
  add_memory_option(c);
}

std::array<double, 4> strategy_weights(const std::string& list) {
  static const char* names[] = {"csi", "dni", "dli", "ali"};
  std::array<double, 4> w{};
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    bool known = false;
    for (int i = 0; i < 4; ++i)
      if (name == names[i]) w[static_cast<std::size_t>(i)] = 1, known = true;
    if (!known) throw InputError("--strategies: unknown strategy '" + name + "' (csi, dni, dli, ali)");
  }
  if (w[0] + w[1] + w[2] + w[3] == 0) throw InputError("--strategies: no strategy given");
  return w;
}

void run_inflate(const InflateArgs& a) {
  const std::string ext = a.output.size() >= 4 ? a.output.substr(a.output.size() - 4) : "";
  if (ext != ".csg" && ext != "scad") throw InputError("inflate writes .scad or .csg, not '" + a.output + "'");
  check_writable(a.output);
  const ScadProgram program = read_openscad_program(a.input);
  opt::InflateOptions o;
  o.steps = a.steps;
  o.seed = a.seed;
  o.weights = strategy_weights(a.strategies);
  opt::InflateReport report;
  const opt::Expr inflated = opt::inflate(program.tree, o, &report);
  ScadWriteOptions w;
  w.csg_style = ext == ".csg";
  w.header = "csgfit inflate (seed 001's generator): " + std::to_string(a.steps) + " steps, seed " + std::to_string(a.seed);
  write_file_atomic(a.output, write_openscad_program(program, inflated, w));
  if (!a.quiet)
    std::fprintf(stderr, "csgfit: size %zu -> %zu (CSI %zu, DNI %zu, DLI %zu, ALI %zu)\n",
                 opt::expression_size(program.tree), opt::expression_size(inflated), report.applied[0],
                 report.applied[1], report.applied[2], report.applied[3]);
}

}  // namespace

Command add_inflate_command(CLI::App& app) {
  return make_command(app, "inflate", "seed 001's redundancy generator: a larger tree of the same solid",
                      add_inflate_options, run_inflate);
}

}  // namespace csgfit::cli
