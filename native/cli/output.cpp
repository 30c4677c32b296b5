#include "output.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "csgfit/io/json.h"
#include "fcstd_writer.h"
#include "scad_writer.h"
#ifdef CSGFIT_WITH_STEP
#include "step_writer.h"
#endif

namespace fs = std::filesystem;

namespace csgfit::cli {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

InputError no_step_support(const std::string& out) {
  return InputError("cannot write '" + out +
                    "': this csgfit was built without STEP support (CSGFIT_BUILD_OCCT=OFF)");
}

#ifdef CSGFIT_WITH_STEP
constexpr bool kWithStep = true;
const char* const kExpected = "(expected .scad, .json, .FCStd or .step)";

void write_step_file(const std::string& out, const Node& tree, const ModelFrame& frame) {
  write_step(tree, frame, out);
}

void write_step_file(const std::string& out, const Node3D& tree, const std::string& source) {
  StepOptions step;
  step.source = source;
  write_step(tree, out, step);
}
#else
constexpr bool kWithStep = false;
const char* const kExpected = "(expected .scad, .json or .FCStd)";

// output_format refuses .step before anything is fitted or read; these are not reached.
void write_step_file(const std::string& out, const Node&, const ModelFrame&) {
  throw no_step_support(out);
}
void write_step_file(const std::string& out, const Node3D&, const std::string&) {
  throw no_step_support(out);
}
#endif

std::string alternative_path(const std::string& out, std::size_t i) {
  fs::path p(out);
  return (p.parent_path() /
          (p.stem().string() + ".alt" + std::to_string(i) + p.extension().string()))
      .string();
}

// One 2D tree in a format that holds one tree.
void write_tree(const std::string& out, OutputFormat format, const Node& tree,
                const FitStats& stats, const ModelFrame& frame, const ScadOptions& scad) {
  if (format == OutputFormat::Step)
    write_step_file(out, tree, frame);
  else
    write_file_atomic(out, to_scad(tree, frame, scad, &stats));
}

// A whole csgfit document, 2D or 3D.
void write_document(const std::string& out, OutputFormat format, const std::string& json_text) {
  if (format == OutputFormat::FCStd)
    write_fcstd(json_text, out);
  else
    write_file_atomic(out, json_text);
}

}  // namespace

bool has_step_support() { return kWithStep; }

OutputFormat output_format(const std::string& out) {
  const std::string ext = lower_extension(out);
  if (ext == ".scad") return OutputFormat::Scad;
  if (ext == ".json") return OutputFormat::Json;
  if (ext == ".fcstd") return OutputFormat::FCStd;
  if (ext == ".step" || ext == ".stp") {
    if (!kWithStep) throw no_step_support(out);
    return OutputFormat::Step;
  }
  throw InputError("unknown output format '" + (ext.empty() ? out : ext) + "' " + kExpected);
}

void check_png_output(const std::string& path, const char* option) {
  if (lower_extension(path) != ".png")
    throw InputError(std::string(option) + " writes PNG: give it a .png name, not '" + path + "'");
  check_writable(path);
}

OutputFormat check_output(const std::string& out, const ModelFrame* frame_2d) {
  const OutputFormat format = output_format(out);
  if (format == OutputFormat::Step && frame_2d && !(frame_2d->thickness > 0))
    throw InputError("cannot write '" + out + "': STEP needs a thickness (give --thickness)");
  check_writable(out);
  return format;
}

void write_output(const std::string& out, const FitResult& result, const ModelFrame& frame,
                  int fn) {
  const OutputFormat format = output_format(out);
  if (format == OutputFormat::Json || format == OutputFormat::FCStd) {
    write_document(out, format, to_json(result, frame));
    return;
  }
  ScadOptions scad;
  scad.fn = fn;
  scad.width_px = result.width;
  scad.height_px = result.height;
  write_tree(out, format, result.tree, result.stats, frame, scad);
  for (std::size_t i = 0; i < result.alternatives.size(); ++i)
    write_tree(alternative_path(out, i + 1), format, result.alternatives[i].tree,
               result.alternatives[i].stats, frame, scad);
}

void write_output(const std::string& out, const Result3D& result) {
  const OutputFormat format = output_format(out);
  if (format == OutputFormat::Scad) {
    write_file_atomic(out, to_scad(result.tree, result.scad));
  } else if (format == OutputFormat::Step) {
    write_step_file(out, result.tree, result.scad.source);
  } else if (!result.document) {
    throw InputError("cannot write '" + out + "': a 3D result exports to .scad or .step");
  } else {
    write_document(out, format, result.document());
  }
}

}  // namespace csgfit::cli
