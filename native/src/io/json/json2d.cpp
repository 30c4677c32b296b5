#include "csgfit/io/json.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/error.h"
#include "io/input_file.h"
#include "io/json/json_fields.h"

namespace csgfit {

namespace {

using json_detail::fail;
using json_detail::finite_field;
using json_detail::member;
using json_detail::ojson;
using json_detail::shared_to_json;
using json_detail::stats_to_json;
using nlohmann::json;

constexpr const char* kSchema = "csgfit/1";
constexpr double kPi = 3.14159265358979323846;
// Deeper trees are not something a fit produces; the limit keeps a hostile file from
// exhausting the stack in the recursive conversion.
constexpr int kMaxDepth = 256;
constexpr long long kMaxCanvas = 1 << 20;
// The largest canvas a fit can have (option_rules::pixel_count): renders of it stay in int range.
constexpr long long kMaxCanvasPixels = 1LL << 30;

// ---- writing -----------------------------------------------------------------------------

ojson node_to_json(const Node& n, double s, const std::string& where) {
  if (!n.is_leaf()) {
    ojson children = ojson::array();
    for (std::size_t i = 0; i < n.children.size(); ++i)
      children.push_back(
          node_to_json(n.children[i], s, where + ".children[" + std::to_string(i) + "]"));
    return ojson{{"op", std::string(to_string(n.kind))}, {"children", std::move(children)}};
  }
  const Primitive& p = n.primitive;
  const std::string at = where + " (" + std::string(to_string(p.kind)) + ")";
  ojson j;
  j["type"] = std::string(to_string(p.kind));
  j["cx"] = finite_field(p.cx * s, at, "cx");
  j["cy"] = finite_field(p.cy * s, at, "cy");
  switch (p.kind) {
    case PrimitiveKind::Rectangle:
      j["w"] = finite_field(p.w * s, at, "w");
      j["h"] = finite_field(p.h * s, at, "h");
      j["angle"] = finite_field(p.angle, at, "angle");
      break;
    case PrimitiveKind::Circle:
      j["r"] = finite_field(p.w / 2 * s, at, "r");
      break;
    case PrimitiveKind::Ellipse:
      j["rx"] = finite_field(p.w / 2 * s, at, "rx");
      j["ry"] = finite_field(p.h / 2 * s, at, "ry");
      j["angle"] = finite_field(p.angle, at, "angle");
      break;
    case PrimitiveKind::Triangle:
      j["w"] = finite_field(p.w * s, at, "w");
      j["h"] = finite_field(p.h * s, at, "h");
      j["angle"] = finite_field(p.angle, at, "angle");
      j["apex"] = finite_field(p.apex, at, "apex");
      break;
  }
  return j;
}

// ---- reading -----------------------------------------------------------------------------

double number(const json& j, const char* key, const std::string& where, bool required,
              double fallback = 0) {
  if (!required && !member(j, key)) return fallback;
  return json_detail::finite_number(j, key, where, json_detail::kNotFinite);
}

double positive(const json& j, const char* key, const std::string& where) {
  const double v = number(j, key, where, true);
  if (!(v > 0)) fail(where, std::string("'") + key + "' must be > 0");
  return v;
}

// A triangle given by its corners, as in the ground-truth files: the longest edge becomes the
// base so that |apex| <= 1, and the corners are ordered so that the height is positive.
Primitive triangle_from_points(const json& pts, double s, const std::string& where) {
  if (!pts.is_array() || pts.size() != 3)
    fail(where, "'points' must be an array of 3 [x, y] pairs");
  double v[3][2];
  for (std::size_t i = 0; i < 3; ++i) {
    const json& q = pts[i];
    if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
      fail(where, "'points' must be an array of 3 [x, y] pairs");
    v[i][0] = finite_field(q[0].get<double>() / s, where, "points");
    v[i][1] = finite_field(q[1].get<double>() / s, where, "points");
  }
  int base = 0;
  double best = -1;
  for (int i = 0; i < 3; ++i) {
    const int k = (i + 1) % 3;
    const double len = std::hypot(v[k][0] - v[i][0], v[k][1] - v[i][1]);
    if (len > best) best = len, base = i;
  }
  const double* a = v[base];
  const double* b = v[(base + 1) % 3];
  const double* c = v[(base + 2) % 3];
  const double w = best;
  if (!(w > 0)) fail(where, "the triangle's points coincide");
  double ux = (b[0] - a[0]) / w, uy = (b[1] - a[1]) / w;
  double h = (c[0] - a[0]) * -uy + (c[1] - a[1]) * ux;
  if (h < 0) std::swap(a, b), ux = -ux, uy = -uy, h = -h;
  if (!(h > 1e-9 * w)) fail(where, "the triangle's points are collinear");
  const double mx = (a[0] + b[0]) / 2, my = (a[1] + b[1]) / 2;
  const double apex = 2 * ((c[0] - mx) * ux + (c[1] - my) * uy) / w;
  const double angle = std::atan2(uy, ux) * 180.0 / kPi;
  return Primitive::triangle(mx - uy * h / 2, my + ux * h / 2, w, h, angle, apex);
}

// A morph's leaf as written: sizes may be 0 (a primitive seen in the other shape only) and the
// angle is the end of its turn, so nothing is normalised.
Primitive leaf_as_written(PrimitiveKind kind, const json& j, double s, const std::string& at) {
  auto size = [&](const char* key) {
    const double v = number(j, key, at, true);
    if (v < 0) fail(at, std::string("'") + key + "' must be >= 0");
    return v / s;
  };
  Primitive p;
  p.kind = kind;
  p.cx = number(j, "cx", at, true) / s;
  p.cy = number(j, "cy", at, true) / s;
  if (kind == PrimitiveKind::Circle) {
    p.w = p.h = 2 * size("r");
    return p;
  }
  p.w = kind == PrimitiveKind::Ellipse ? 2 * size("rx") : size("w");
  p.h = kind == PrimitiveKind::Ellipse ? 2 * size("ry") : size("h");
  p.angle = number(j, "angle", at, false);
  if (kind == PrimitiveKind::Triangle) p.apex = number(j, "apex", at, false);
  return p;
}

Node node_from(const json& j, double s, const std::string& where, int depth, bool as_written) {
  if (depth > kMaxDepth) fail(where, "tree nested deeper than " + std::to_string(kMaxDepth));
  if (!j.is_object()) fail(where, "a node must be an object");
  const json* op = member(j, "op");
  const json* type = member(j, "type");
  if (op && type) fail(where, "a node has either 'op' or 'type', not both");
  if (op) {
    if (!op->is_string()) fail(where, "'op' must be a string");
    const std::string name = op->get<std::string>();
    NodeKind kind;
    if (!json_detail::node_kind_from_name(name, &kind)) {
      fail(where, "unknown op '" + name + "' (expected union, difference or intersection)");
    }
    const json* kids = member(j, "children");
    if (!kids || !kids->is_array()) fail(where, "'" + name + "' needs a 'children' array");
    if (kids->empty()) fail(where, "'" + name + "' has no children");
    std::vector<Node> children;
    children.reserve(kids->size());
    for (std::size_t i = 0; i < kids->size(); ++i)
      children.push_back(
          node_from((*kids)[i], s, where + ".children[" + std::to_string(i) + "]", depth + 1,
                    as_written));
    return Node::op(kind, std::move(children));
  }
  if (!type) fail(where, "a node needs 'op' (operator) or 'type' (primitive)");
  if (!type->is_string()) fail(where, "'type' must be a string");
  PrimitiveKind kind;
  try {
    kind = primitive_kind_from_string(type->get<std::string>());
  } catch (const std::invalid_argument& e) {
    fail(where, e.what());
  }
  const std::string at = where + " (" + type->get<std::string>() + ")";
  if (as_written) return Node::leaf(leaf_as_written(kind, j, s, at));
  if (kind == PrimitiveKind::Triangle && member(j, "points"))
    return Node::leaf(triangle_from_points(*member(j, "points"), s, at));
  const double cx = number(j, "cx", at, true) / s;
  const double cy = number(j, "cy", at, true) / s;
  switch (kind) {
    case PrimitiveKind::Rectangle:
      return Node::leaf(Primitive::rectangle(cx, cy, positive(j, "w", at) / s,
                                             positive(j, "h", at) / s,
                                             number(j, "angle", at, false)));
    case PrimitiveKind::Circle:
      return Node::leaf(Primitive::circle(cx, cy, positive(j, "r", at) / s));
    case PrimitiveKind::Ellipse:
      return Node::leaf(Primitive::ellipse(cx, cy, positive(j, "rx", at) / s,
                                           positive(j, "ry", at) / s,
                                           number(j, "angle", at, false)));
    case PrimitiveKind::Triangle:
      return Node::leaf(Primitive::triangle(cx, cy, positive(j, "w", at) / s,
                                            positive(j, "h", at) / s,
                                            number(j, "angle", at, false),
                                            number(j, "apex", at, false)));
  }
  fail(at, "unknown primitive");
}

std::size_t count(const json& j, const char* key, const std::string& where) {
  const json* v = member(j, key);
  if (!v || v->is_null()) return 0;
  if (!v->is_number_integer() || v->get<long long>() < 0)
    fail(where, std::string("'") + key + "' must be a non-negative integer");
  return static_cast<std::size_t>(v->get<long long>());
}

double stat_number(const json& j, const char* key, const std::string& where) {
  const json* v = member(j, key);
  if (!v || v->is_null()) return 0;
  return number(j, key, where, true);
}

FitStats stats_from(const json& j, const std::string& where) {
  FitStats st;
  if (!j.is_object()) fail(where, "'stats' must be an object");
  st.k = stat_number(j, "k", where);
  st.score = stat_number(j, "score", where);
  st.excess = count(j, "excess", where);
  st.uncovered = count(j, "uncovered", where);
  st.primitives = count(j, "primitives", where);
  st.iou = stat_number(j, "iou", where);
  st.evaluations = count(j, "evaluations", where);
  st.trees = count(j, "trees", where);
  st.seconds = stat_number(j, "seconds", where);
  if (const json* r = member(j, "stop_reason"); r && !r->is_null()) {
    if (!r->is_string()) fail(where, "'stop_reason' must be a string");
    st.stop_reason = r->get<std::string>();
  }
  return st;
}

json parse(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    std::string msg = e.what();
    // nlohmann's messages start with "[json.exception.parse_error.101] parse error at ...".
    const std::size_t close = msg.find("] ");
    if (close != std::string::npos) msg = msg.substr(close + 2);
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    throw InputError("JSON: " + msg);
  }
}

}  // namespace

namespace json_detail {

Node read_node2d(const json& j, double pixel_size, const std::string& where, bool as_written) {
  return node_from(j, pixel_size, where, 0, as_written);
}

FitStats read_stats2d(const json& j, const std::string& where) { return stats_from(j, where); }

}  // namespace json_detail

std::string to_json(const FitResult& result, const ModelFrame& frame) {
  const double s = frame.pixel_size;
  if (!std::isfinite(s) || !(s > 0)) throw InputError("JSON: pixel size must be a positive number");
  if (!std::isfinite(frame.thickness) || frame.thickness < 0)
    throw InputError("JSON: thickness must be a finite number >= 0");
  ojson doc;
  doc["schema"] = kSchema;
  doc["dimension"] = 2;
  doc["units"] = "mm";
  doc["canvas"] = ojson{{"width_px", result.width},
                       {"height_px", result.height},
                       {"pixel_size", s},
                       {"thickness", frame.thickness}};
  doc["source"] = frame.source;
  doc["tree"] = node_to_json(result.tree, s, "tree");
  doc["shared_dimensions"] = shared_to_json(result.tree, s);
  doc["stats"] = stats_to_json(result.stats);
  ojson alts = ojson::array();
  for (std::size_t i = 0; i < result.alternatives.size(); ++i) {
    const FitTree& a = result.alternatives[i];
    alts.push_back(
        ojson{{"tree", node_to_json(a.tree, s, "alternatives[" + std::to_string(i) + "].tree")},
              {"shared_dimensions", shared_to_json(a.tree, s)},
              {"stats", stats_to_json(a.stats)}});
  }
  doc["alternatives"] = std::move(alts);
  // Invalid UTF-8 in a file name must not abort the write; replace it.
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

static FitResult from_json_checked(const std::string& text, ModelFrame* frame, bool as_written) {
  const json doc = parse(text);
  if (!doc.is_object()) throw InputError("JSON: the document must be an object");
  FitResult result;
  ModelFrame f;
  if (!member(doc, "schema")) {
    if (member(doc, "op") || member(doc, "type")) {
      // A bare tree such as a ground-truth file: pixel units, canvas unknown.
      result.tree = node_from(doc, 1.0, "tree", 0, false);
      result.stats.primitives = result.tree.primitive_count();
      if (frame) *frame = f;
      return result;
    }
    throw InputError("JSON: missing 'schema' (expected \"" + std::string(kSchema) + "\")");
  }
  const json& schema = doc["schema"];
  if (!schema.is_string() || schema.get<std::string>() != kSchema)
    throw InputError("JSON: unsupported schema " + schema.dump() + " (this build reads \"" +
                     kSchema + "\")");
  if (const json* d = member(doc, "dimension"); d && !(d->is_number_integer() && *d == 2))
    throw InputError("JSON: 'dimension' must be 2 (3D trees are not supported here)");
  if (const json* u = member(doc, "units"); u && !(u->is_string() && *u == "mm"))
    throw InputError("JSON: 'units' must be \"mm\"");

  const json* canvas = member(doc, "canvas");
  if (!canvas || !canvas->is_object()) throw InputError("JSON: missing object 'canvas'");
  for (const char* key : {"width_px", "height_px"}) {
    const json* v = member(*canvas, key);
    if (!v || !v->is_number_integer() || v->get<long long>() < 0 ||
        v->get<long long>() > kMaxCanvas)
      fail("canvas", std::string("'") + key + "' must be an integer from 0 to " +
                         std::to_string(kMaxCanvas));
  }
  result.width = (*canvas)["width_px"].get<int>();
  result.height = (*canvas)["height_px"].get<int>();
  if (result.width == 0 || result.height == 0 ||
      static_cast<long long>(result.width) * result.height > kMaxCanvasPixels)
    fail("canvas", std::to_string(result.width) + " x " + std::to_string(result.height) +
                       " pixels: a fit's canvas has 1 to " + std::to_string(kMaxCanvasPixels) +
                       " pixels");
  f.pixel_size = positive(*canvas, "pixel_size", "canvas");
  f.thickness = number(*canvas, "thickness", "canvas", false);
  if (f.thickness < 0) fail("canvas", "'thickness' must be >= 0");
  if (const json* src = member(doc, "source"); src && !src->is_null()) {
    if (!src->is_string()) throw InputError("JSON: 'source' must be a string");
    f.source = src->get<std::string>();
  }

  const json* tree = member(doc, "tree");
  if (!tree) throw InputError("JSON: missing 'tree'");
  result.tree = node_from(*tree, f.pixel_size, "tree", 0, as_written);
  if (const json* st = member(doc, "stats"); st && !st->is_null())
    result.stats = stats_from(*st, "stats");
  if (const json* alts = member(doc, "alternatives"); alts && !alts->is_null()) {
    if (!alts->is_array()) throw InputError("JSON: 'alternatives' must be an array");
    for (std::size_t i = 0; i < alts->size(); ++i) {
      const std::string where = "alternatives[" + std::to_string(i) + "]";
      const json& a = (*alts)[i];
      if (!a.is_object() || !member(a, "tree")) fail(where, "needs a 'tree'");
      FitTree ft;
      ft.tree = node_from(a["tree"], f.pixel_size, where + ".tree", 0, false);
      if (const json* st = member(a, "stats"); st && !st->is_null())
        ft.stats = stats_from(*st, where + ".stats");
      result.alternatives.push_back(std::move(ft));
    }
  }
  if (frame) *frame = f;
  return result;
}

std::string read_json_file(const std::string& path) {
  // A document of 10^5 primitives is under 50 MB.
  return io_detail::read_whole_file(path, 256LL << 20, "too large for a csgfit document",
                                    io_detail::FileContent::Text);
}

namespace json_detail {

FitResult read_document2d(const std::string& text, ModelFrame* frame, bool as_written) {
  try {
    return from_json_checked(text, frame, as_written);
  } catch (const json::exception& e) {
    throw InputError(std::string("JSON: ") + e.what());
  }
}

}  // namespace json_detail

FitResult from_json(const std::string& text, ModelFrame* frame) {
  try {
    return from_json_checked(text, frame, false);
  } catch (const json::exception& e) {
    // Every field is type-checked above; this is a safety net that keeps the one-line contract.
    throw InputError(std::string("JSON: ") + e.what());
  }
}

Node node_from_json(const std::string& text, double pixel_size) {
  if (!std::isfinite(pixel_size) || !(pixel_size > 0))
    throw InputError("JSON: pixel size must be a positive number");
  return node_from(parse(text), pixel_size, "tree", 0, false);
}

Node flip_y(const Node& tree, double height) {
  if (!tree.is_leaf()) {
    std::vector<Node> children;
    children.reserve(tree.children.size());
    for (const Node& c : tree.children) children.push_back(flip_y(c, height));
    return Node::op(tree.kind, std::move(children));
  }
  // Mirroring turns a rotation by a into one by -a; rectangles and ellipses are symmetric about
  // their local x axis, a triangle's mirror image is itself turned by 180 degrees with the apex
  // on the other side.
  Primitive p = tree.primitive;
  p.cy = height - p.cy;
  p.angle = -p.angle;
  if (p.kind == PrimitiveKind::Triangle) {
    p.angle += 180.0;
    p.apex = -p.apex;
  }
  p.normalize();
  return Node::leaf(p);
}

}  // namespace csgfit
