
#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/json.h"
#include "fcstd_writer.h"
#include "option_checks.h"
#include "output.h"
#include "scad_writer.h"

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

// A 2D morph document: the animated .scad, the document again, or the FreeCAD tree driven by
// its `morph` cell. STEP holds one solid, and a morph is two.
void export_morph(const ExportArgs& a, OutputFormat format, const std::string& text) {
  if (format == OutputFormat::Step)
    throw InputError("cannot write '" + a.output + "': a morph holds two solids (export .scad, .json or .FCStd)");
  ModelFrame frame;
  std::string source_b;
  TurnDirection rotate = TurnDirection::Shortest;
  const MorphResult r = morph_from_json(text, &frame, &source_b, &rotate);
  if (format == OutputFormat::Scad) {
    ScadOptions scad;
    scad.fn = a.fn;
    scad.width_px = r.width;
    scad.height_px = r.height;
    write_file_atomic(a.output, to_scad_morph(r.a, r.b, frame, source_b, scad, &r.stats_a));
    return;
  }
  const std::string doc = to_json_morph(r, frame, source_b, rotate);
  if (format == OutputFormat::FCStd)
    write_fcstd(doc, a.output);
  else
    write_file_atomic(a.output, doc);
}

void run_export(const ExportArgs& a) {
  const OutputFormat format = check_output(a.output);
  const std::string text = read_json_file(a.input);
  if (is_json_morph(text)) {
    export_morph(a, format, text);
    return;
  }
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
