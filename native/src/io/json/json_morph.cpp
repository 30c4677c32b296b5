// A morph's JSON: the document of shape A (2D or 3D) with a "morph" object holding tree B, its
// stats and where each leaf is seen (docs/JSON_SCHEMA.md). The single-tree writers make both
// trees, so a morph's trees are written exactly as fits' are.
#include <nlohmann/json.hpp>

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

}  // namespace csgfit
