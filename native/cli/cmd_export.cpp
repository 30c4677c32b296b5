
#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "option_checks.h"
#include "output.h"

namespace csgfit::cli {

namespace {

struct ExportArgs {
  std::string input, output;
  int fn = 96;
  const CLI::Option* fn_option = nullptr;  // unless given, a 3D tree keeps the mesh command's $fn
};

void add_export_options(CLI::App& exporter, ExportArgs& a) {
  exporter.add_option("input", a.input, "csgfit .json result")->required();
  exporter.add_option("-o,--output", a.output, "output: .scad, .json, .FCStd or .step")->required();
  a.fn_option = exporter.add_option("--fn", a.fn, "OpenSCAD $fn")->check(obeys(option_rules::fn));
  add_memory_option(exporter);
}

void run_export(const ExportArgs& a) {
  check_output(a.output);
  const std::string text = read_json_file(a.input);
  if (is_json3d(text)) {
    std::string source;
    const Node3D tree = from_json3d(text, &source);
    Result3D result{tree, {}, {}};
    if (a.fn_option->count() > 0) result.scad.fn = a.fn;
    result.scad.source = source;
    write_output(a.output, result);
    return;
  }
  ModelFrame frame;
  const FitResult result = from_json(text, &frame);
  write_output(a.output, result, frame, a.fn);
}

}  // namespace

Command add_export_command(CLI::App& app) {
  return make_command(app, "export",
                      "convert a csgfit .json result to .scad, .json, .FCStd or .step",
                      add_export_options, run_export);
}

}  // namespace csgfit::cli
