// The JSON form of a fitted tree (schema: docs/JSON_SCHEMA.md).
#pragma once

#include <string>

#include "csgfit/fit.h"
#include "csgfit/tree.h"

namespace csgfit {

/// How solver coordinates (pixel units, y up) map to model units.
struct ModelFrame {
  double pixel_size = 1.0;   ///< model units (mm) per pixel
  double thickness = 0.0;    ///< > 0: the 2D result is extruded to this height
  std::string source;        ///< input file name, for the record
};

/// Serialises a result (best tree, stats, alternatives) as JSON text, schema version 1.
std::string to_json(const FitResult& result, const ModelFrame& frame);

/// Parses JSON written by to_json back into a result (tree and canvas; stats as stored).
/// Throws InputError on malformed input or an unknown schema version.
/// A bare node (no "schema" envelope) such as the benchmark ground-truth files
/// (../shared/benchmarks/2d/*.gt.json) are also accepted: tree in pixel units, no canvas.
FitResult from_json(const std::string& text, ModelFrame* frame = nullptr);

/// Parses one bare tree node ({"op": ..., "children": [...]} or {"type": ..., ...}) whose
/// coordinates are in units of `pixel_size` model units per pixel (1 = already pixel units, as
/// in the ground-truth files). Besides the schema's primitives it reads "rect", and triangles
/// given as "points": [[x, y], [x, y], [x, y]]. Throws InputError naming the bad field and node.
Node node_from_json(const std::string& text, double pixel_size = 1.0);

/// The tree mirrored top to bottom on a canvas `height` pixels high (y -> height - y), for trees
/// written in image coordinates (y down). The benchmark files part_*.gt.json are such trees
/// (measured: render(flip_y(node_from_json(gt), 128), 128, 128) equals the benchmark PNG
/// pixel for pixel); eye_in_diamond.gt.json is symmetric, so either reading works.
Node flip_y(const Node& tree, double height);

}  // namespace csgfit
