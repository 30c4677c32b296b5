// The JSON form of a fitted tree (schema: docs/JSON_SCHEMA.md).
#pragma once

#include <string>
#include <vector>

#include "csgfit/model/frame.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/pipeline/fit_morph.h"
#include "csgfit/pipeline/fit_points.h"
#include "csgfit/pipeline/fit_range.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

/// The text of a csgfit .json document (2D or 3D) at `path`, read under a size limit: a
/// missing, empty, binary or oversized file is an InputError naming it.
std::string read_json_file(const std::string& path);

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

/// The fit as JSON: schema "csgfit/1" with "dimension": 3 (lengths in the mesh's units):
/// {"schema", "dimension": 3, "units", "source", "grid": {"nx", "ny", "nz", "origin": [x, y, z],
/// "voxel_size"}, "tree", "stats"}. Operator nodes as in 2D ({"op", "children"}); a primitive is
/// {"type", "center": [x, y, z], "rotation": [w, x, y, z] (unit quaternion, local -> model),
/// "euler_deg": [a, b, c] (OpenSCAD rotate()), then its dimensions: box "size": [x, y, z];
/// sphere "r"; cylinder "r", "h"; cone "r1" (bottom, local z = -h/2), "r2", "h"; ellipsoid
/// "radii": [rx, ry, rz]; torus "R", "r"; prism "w", "h", "depth", "apex"}. Throws
/// InputError for a non-finite value.
/// `frame` is the rotation of the fitting grid (grid -> mesh coordinates; written as "frame":
/// [w, x, y, z]); the tree itself is always in mesh coordinates. "sweeps", when the tree has
/// any (find_sweeps), gives each one's node, kind, frame, height and its leaves' sections in
/// its plane, for readers that draw them as extrusions and revolutions (range and point
/// documents carry it too).
std::string to_json3d(const FitResult3D& result, const VoxelGrid& grid, const std::string& source,
                      const Quaternion& frame = {});

/// The "sweeps" block to_json3d writes for `tree`, on its own: a JSON array, empty when the
/// tree has no sweep (for readers of trees that came without one, such as csgfit.find_sweeps).
std::string to_json_sweeps(const Node3D& tree);

/// A range fit as JSON: the 3D document's "schema", "dimension", "units", "source", "tree" and
/// "stats" (no grid: the input was points), with "sources" (every view), "views" (each view's
/// silhouette_iou and depth_error as its sensor sees the tree), "precedence_graph" (seed 002:
/// "subobjects", "nodes" with kind, sign, order, subobject, dims, the primitive and its patch
/// indices, "arcs" with from, to and kind "subtracting" or "appending") and "patches" (kind,
/// points, convex, rms of each detected surface). docs/JSON_SCHEMA.md describes it.
std::string to_json_range(const RangeFitResult& result, const std::vector<std::string>& sources);

/// A point-cloud fit (seed 004) as JSON: the 3D document's "schema", "dimension", "units",
/// "source", "sources", "tree" (NURBS terminals as "nurbs" leaves: degree, counts, knots, control
/// points) and "stats", with "points": scan, count, search, islands, generations, first_tree, the
/// fitness and its terms, mean_distance, nodes, patch_rms (docs/JSON_SCHEMA.md).
std::string to_json_points(const PointsFitResult& result, const std::vector<std::string>& sources);

/// A 2D morph as JSON: shape A's document (canvas, "tree", "stats") with "morph": {"source_b",
/// "tree_b", "stats_b", "rotate", "leaves": [{"in_a", "in_b"}, ...]} (docs/JSON_SCHEMA.md).
/// tree_b has tree's structure; every number of the frame at t is a + (b - a) t.
std::string to_json_morph(const MorphResult& result, const ModelFrame& frame,
                          const std::string& source_b, TurnDirection rotate);
/// Whether `text` is a JSON document with a "morph" object (false for unparsable text).
bool is_json_morph(const std::string& text);
/// Reads a 2D morph written by to_json_morph: both trees as written (sizes of 0, unwrapped
/// angles), the frame, B's source and the turn direction. Throws InputError naming the field
/// when malformed, when tree_b differs from tree in structure, or for a 3D morph.
MorphResult morph_from_json(const std::string& text, ModelFrame* frame = nullptr,
                            std::string* source_b = nullptr, TurnDirection* rotate = nullptr);
/// A 3D morph as JSON: shape A's 3D document with the same "morph" object (no "rotate": 3D
/// turns take the short arc).
std::string to_json_morph3d(const MorphResult3D& result, const VoxelGrid& grid,
                            const std::string& source_a, const std::string& source_b);

/// Whether `text` is a JSON document with "dimension": 3 (false for 2D or unparsable text).
bool is_json3d(const std::string& text);
/// Reads the tree of a document written by to_json3d (`source` gets its "source"). The
/// quaternion "rotation" is used (euler_deg only when it is absent); the grid and stats are
/// not read. Throws InputError naming the bad field and node.
Node3D from_json3d(const std::string& text, std::string* source = nullptr);

}  // namespace csgfit
