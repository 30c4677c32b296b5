// What the 2D and 3D JSON documents share: the one-line errors that name the node and the
// field, typed field access, and the stats block. Templates take either nlohmann::json (2D
// reads with it) or ordered_json (3D reads, and both write, with it).
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "csgfit/model/frame.h"
#include "csgfit/model/shared_dimensions.h"
#include "csgfit/model/tree.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/search/stats.h"

namespace csgfit::json_detail {

// Written documents keep the schema's key order (schema first, type before coordinates).
using ojson = nlohmann::ordered_json;

// The two wordings for a NaN or infinite field: 2D documents say the first, 3D ones the second.
constexpr const char* kNotFinite = "is not a finite number";
constexpr const char* kNotFinite3D = "is not finite";

/// Throws InputError("JSON: <where>: <what>"); `where` names the node, e.g. "tree.children[1]".
[[noreturn]] void fail(const std::string& where, const std::string& what);

/// v, or fails with "'field' <not_finite>" when it is NaN or infinite.
inline double finite_field(double v, const std::string& where, const char* field,
                           const char* not_finite = kNotFinite) {
  if (!std::isfinite(v)) fail(where, std::string("'") + field + "' " + not_finite);
  return v;
}

/// The member `key` of the object j; null when there is none.
template <typename Json>
const Json* member(const Json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

/// The finite number `key` of j; fails with "missing number 'key'", "'key' must be a number"
/// or "'key' <not_finite>".
template <typename Json>
double finite_number(const Json& j, const char* key, const std::string& where,
                     const char* not_finite) {
  const Json* v = member(j, key);
  if (!v) fail(where, std::string("missing number '") + key + "'");
  if (!v->is_number()) fail(where, std::string("'") + key + "' must be a number");
  return finite_field(v->template get<double>(), where, key, not_finite);
}

/// The operator named "union", "difference" or "intersection"; false for any other name.
bool node_kind_from_name(const std::string& name, NodeKind* kind);

/// The 2D reader (json2d.cpp) for a morph's document (json_morph.cpp): as_written keeps sizes
/// of 0 and unwrapped angles, as a morph's trees have them.
FitResult read_document2d(const std::string& text, ModelFrame* frame, bool as_written);
Node read_node2d(const nlohmann::json& j, double pixel_size, const std::string& where, bool as_written);
FitStats read_stats2d(const nlohmann::json& j, const std::string& where);

/// The tree's shared dimensions (shared_dimensions.h) for readers that build parametric models,
/// values times `scale` (mm per pixel in 2D, 1 in 3D): written from the values, never read back
/// (the values are the truth).
template <typename NodeT>
ojson shared_to_json(const NodeT& tree, double scale) {
  ojson out = ojson::array();
  const auto ls = leaves(tree);
  for (const SharedDimension& d : shared_dimensions(tree)) {
    const DimensionUse& first = d.uses.front();
    const double v = field_value(*ls[first.leaf], first.field) * scale;
    ojson uses = ojson::array();
    for (const DimensionUse& u : d.uses)
      uses.push_back(ojson{{"leaf", u.leaf}, {"field", std::string(field_name(u.field))}});
    out.push_back(ojson{{"name", d.name},
                        {"value", finite_field(v, "shared dimension " + d.name, "value")},
                        {"uses", std::move(uses)}});
  }
  return out;
}

/// The "stats" object of both dimensions; a NaN or infinite statistic is written as null
/// (JSON has neither), and read back as 0.
ojson stats_to_json(const FitStats& st);

}  // namespace csgfit::json_detail
