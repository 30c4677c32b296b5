// csgfit optimize's reading and writing: which reader the input's extension picks, the
// optimiser on the tree it holds, and the output in the format OUT names.
#pragma once

#include <string>

#include "csgfit/optimise/optimize_tree.h"

namespace csgfit::cli {

struct OptimizedTree {
  opt::OptimizeReport report;
  std::size_t primitives_before = 0, primitives_after = 0;
};

/// Reads `input` (.scad, .csg, .json), optimises its tree, writes `output` (.scad, .csg,
/// .json, .FCStd, .step; .csg only from an OpenSCAD input). Throws InputError.
OptimizedTree optimize_file(const std::string& input, const std::string& output,
                            const opt::OptimizeOptions& options);

}  // namespace csgfit::cli
