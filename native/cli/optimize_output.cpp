#include "optimize_output.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/json.h"
#include "csgfit/io/openscad_program.h"
#include "csgfit/optimise/tree_expression.h"
#include "output.h"

namespace csgfit::cli {
namespace {

std::string extension_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string header_of(const std::string& input, const opt::OptimizeReport& r) {
  char line[160];
  std::snprintf(line, sizeof line, "size %zu -> %zu, proximity %.3f -> %.3f", r.size_before, r.size_after,
                r.proximity_before, r.proximity_after);
  return "csgfit optimize " + std::filesystem::path(input).filename().string() + "\n" + line;
}

// A 3D tree with what its .json and .FCStd need: a document of the tree alone.
void write_tree3d(const std::string& out, const Node3D& tree, const std::string& source) {
  Result3D result{tree, {}, {}};
  result.scad.source = source;
  result.document = [&tree, &source] {
    FitResult3D fit{tree, {}};
    fit.stats.primitives = tree.primitive_count();
    fit.stats.stop_reason = "optimized";
    return to_json3d(fit, VoxelGrid(1, 1, 1), source);
  };
  write_output(out, result);
}

OptimizedTree from_openscad(const std::string& in, const std::string& out, const opt::OptimizeOptions& o) {
  const ScadProgram program = read_openscad_program(in);
  opt::OptimizeResult r = program.dimension == 3 ? opt::optimize_tree(program.tree, program.halfspaces3, o)
                                                 : opt::optimize_tree(program.tree, program.halfspaces2, o);
  const std::string ext = extension_of(out);
  if (ext == ".scad" || ext == ".csg") {
    ScadWriteOptions w;
    w.csg_style = ext == ".csg";
    w.header = header_of(in, r.report);
    write_file_atomic(out, write_openscad_program(program, r.tree, w));
  } else {
    write_tree3d(out, node3d_of(program, r.tree), std::filesystem::path(in).filename().string());
  }
  return {r.report, opt::literal_count(program.tree), opt::literal_count(r.tree)};
}

OptimizedTree from_json(const std::string& in, const std::string& out, const opt::OptimizeOptions& o) {
  if (extension_of(out) == ".csg")
    throw InputError("a csgfit .json tree is written as .scad, .json, .FCStd or .step (not .csg)");
  const std::string text = read_json_file(in);
  OptimizedTree done;
  if (is_json3d(text)) {
    std::string source;
    const Node3D tree = from_json3d(text, &source);
    const Node3D better = opt::optimize_csg_tree(tree, o, &done.report);
    done.primitives_before = tree.primitive_count();
    done.primitives_after = better.primitive_count();
    write_tree3d(out, better, source);
    return done;
  }
  ModelFrame frame;
  FitResult result = from_json(text, &frame);
  done.primitives_before = result.tree.primitive_count();
  result.tree = opt::optimize_csg_tree(result.tree, o, &done.report);
  result.stats.primitives = done.primitives_after = result.tree.primitive_count();
  write_output(out, result, frame, 96);
  return done;
}

}  // namespace

OptimizedTree optimize_file(const std::string& input, const std::string& output, const opt::OptimizeOptions& o) {
  const std::string in_ext = extension_of(input), out_ext = extension_of(output);
  if (out_ext == ".csg") check_writable(output);
  else check_output(output);
  if (in_ext == ".scad" || in_ext == ".csg") return from_openscad(input, output, o);
  if (in_ext == ".json") return from_json(input, output, o);
  throw InputError("optimize reads .scad, .csg or csgfit .json, not '" + input + "'");
}

}  // namespace csgfit::cli
