// A morph's JSON: the document of shape A (2D or 3D) with a "morph" object holding tree B, its
// stats and where each leaf is seen (docs/JSON_SCHEMA.md). The single-tree writers make both
// trees, so a morph's trees are written exactly as fits' are.
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "json_fields.h"

namespace csgfit {

namespace {

using json_detail::ojson;

const char* turn_name(TurnDirection d) {
  switch (d) {
    case TurnDirection::Clockwise: return "cw";
    case TurnDirection::CounterClockwise: return "ccw";
    case TurnDirection::Shortest: break;
  }
  return "shortest";
}

template <typename Tree>
ojson morph_object(const MorphPair<Tree>& pair, const ojson& doc_b, const std::string& source_b) {
  ojson m;
  m["source_b"] = source_b;
  m["tree_b"] = doc_b.at("tree");
  m["stats_b"] = doc_b.at("stats");
  ojson seen = ojson::array();
  for (const MorphLeaf& l : pair.leaves) seen.push_back(ojson{{"in_a", l.in_a}, {"in_b", l.in_b}});
  m["leaves"] = std::move(seen);
  return m;
}

using json_detail::fail;
using json_detail::member;

std::string text_field(const nlohmann::json& m, const char* key) {
  const nlohmann::json* v = member(m, key);
  if (!v || v->is_null()) return {};
  if (!v->is_string()) fail("morph", std::string("'") + key + "' must be a string");
  return v->get<std::string>();
}

// Where each leaf is seen; every leaf in both shapes when the document does not say.
std::vector<MorphLeaf> leaves_from(const nlohmann::json& m, std::size_t count) {
  std::vector<MorphLeaf> out(count);
  const nlohmann::json* v = member(m, "leaves");
  if (!v || v->is_null()) return out;
  if (!v->is_array() || v->size() != count)
    fail("morph", "'leaves' must be an array of " + std::to_string(count) + " objects");
  for (std::size_t i = 0; i < count; ++i) {
    const nlohmann::json& l = (*v)[i];
    const nlohmann::json *a = l.is_object() ? member(l, "in_a") : nullptr,
                         *b = l.is_object() ? member(l, "in_b") : nullptr;
    if (!a || !b || !a->is_boolean() || !b->is_boolean())
      fail("morph.leaves[" + std::to_string(i) + "]", "needs booleans 'in_a' and 'in_b'");
    out[i] = {a->get<bool>(), b->get<bool>()};
  }
  return out;
}

std::string dump(const ojson& doc) {
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

}  // namespace

std::string to_json_morph(const MorphResult& result, const ModelFrame& frame,
                          const std::string& source_b, TurnDirection rotate) {
  FitResult one;
  one.width = result.width;
  one.height = result.height;
  one.tree = result.a;
  one.stats = result.stats_a;
  ojson doc = ojson::parse(to_json(one, frame));
  one.tree = result.b;
  one.stats = result.stats_b;
  const ojson doc_b = ojson::parse(to_json(one, frame));
  doc.erase("alternatives");
  doc["morph"] = morph_object(result, doc_b, source_b);
  doc["morph"]["rotate"] = turn_name(rotate);
  return dump(doc);
}

std::string to_json_morph3d(const MorphResult3D& result, const VoxelGrid& grid,
                            const std::string& source_a, const std::string& source_b) {
  ojson doc = ojson::parse(to_json3d(FitResult3D{result.a, result.stats_a}, grid, source_a));
  const ojson doc_b = ojson::parse(to_json3d(FitResult3D{result.b, result.stats_b}, grid, source_b));
  doc["morph"] = morph_object(result, doc_b, source_b);
  return dump(doc);
}

bool is_json_morph(const std::string& text) {
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  return doc.is_object() && doc.contains("morph");
}

MorphResult morph_from_json(const std::string& text, ModelFrame* frame, std::string* source_b,
                            TurnDirection* rotate) {
  if (is_json3d(text))
    throw InputError("JSON: a 3D morph is written by csgfit morph itself (.scad, .json, .FCStd)");
  ModelFrame f;
  const FitResult a = json_detail::read_document2d(text, &f, true);
  const nlohmann::json doc = nlohmann::json::parse(text);
  const nlohmann::json* m = member(doc, "morph");
  if (!m || !m->is_object() || !member(*m, "tree_b")) fail("morph", "needs an object with 'tree_b'");
  MorphResult r;
  r.a = a.tree;
  r.stats_a = a.stats;
  r.width = a.width;
  r.height = a.height;
  r.b = json_detail::read_node2d((*m)["tree_b"], f.pixel_size, "morph.tree_b", true);
  try {
    interpolate(r.a, r.b, 0);
  } catch (const std::invalid_argument& e) {
    fail("morph.tree_b", e.what());
  }
  if (const nlohmann::json* st = member(*m, "stats_b"); st && !st->is_null())
    r.stats_b = json_detail::read_stats2d(*st, "morph.stats_b");
  r.leaves = leaves_from(*m, r.a.primitive_count());
  if (frame) *frame = f;
  if (source_b) *source_b = text_field(*m, "source_b");
  if (rotate) {
    const std::string name = text_field(*m, "rotate");
    try {
      *rotate = name.empty() ? TurnDirection::Shortest : turn_direction_from_string(name);
    } catch (const std::invalid_argument& e) {
      fail("morph", e.what());
    }
  }
  return r;
}

}  // namespace csgfit
