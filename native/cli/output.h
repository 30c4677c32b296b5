// The one place where OUT's extension picks a format and a writer, for every command and for
// 2D and 3D results alike, with the checks that let a bad OUT fail before a fit starts.
#pragma once

#include <functional>
#include <string>

#include "csgfit/io/files.h"  // check_writable
#include "csgfit/model/frame.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "scad_writer3d.h"

namespace csgfit::cli {

enum class OutputFormat { Scad, Json, FCStd, Step };

/// Whether this csgfit writes STEP (it does unless built with CSGFIT_BUILD_OCCT=OFF).
bool has_step_support();

/// The format that OUT's extension (any case) names. Throws InputError for an unknown
/// extension, and for .step / .stp in a build without STEP.
OutputFormat output_format(const std::string& out);

/// The checks on a PNG output (`option` names it: "--preview"): a .png name, in a folder that
/// takes a new file. Throws InputError.
void check_png_output(const std::string& path, const char* option);

/// The checks a command makes on OUT before it fits or reads anything: its format and its
/// folder. A 2D fit passes its frame, whose thickness a STEP file needs.
OutputFormat check_output(const std::string& out, const ModelFrame* frame_2d = nullptr);

/// Writes a 2D result to `out`. .scad and .step hold one tree, so the alternatives go to files
/// of their own (OUT.alt1.scad, ...); .json and .FCStd carry them inside. `fn` is the .scad's $fn.
void write_output(const std::string& out, const FitResult& result, const ModelFrame& frame, int fn);

/// A 3D tree and what its formats need besides it.
struct Result3D {
  const Node3D& tree;
  ScadOptions3D scad;  ///< its source also names the STEP product
  /// The csgfit document of a fit (.json and .FCStd are written from it); empty for a tree
  /// read back from a document, which has no grid or statistics and goes only to .scad or .step.
  std::function<std::string()> document;
};

/// Writes a 3D result to `out`.
void write_output(const std::string& out, const Result3D& result);

}  // namespace csgfit::cli
