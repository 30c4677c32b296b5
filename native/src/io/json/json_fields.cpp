#include "io/json/json_fields.h"

#include "csgfit/error.h"

namespace csgfit::json_detail {

namespace {

ojson number_or_null(double v) { return std::isfinite(v) ? ojson(v) : ojson(nullptr); }

}  // namespace

void fail(const std::string& where, const std::string& what) {
  throw InputError("JSON: " + where + ": " + what);
}

bool node_kind_from_name(const std::string& name, NodeKind* kind) {
  if (name == "union") {
    *kind = NodeKind::Union;
  } else if (name == "difference") {
    *kind = NodeKind::Difference;
  } else if (name == "intersection") {
    *kind = NodeKind::Intersection;
  } else {
    return false;
  }
  return true;
}

ojson stats_to_json(const FitStats& st) {
  return ojson{{"k", number_or_null(st.k)},
               {"score", number_or_null(st.score)},
               {"excess", st.excess},
               {"uncovered", st.uncovered},
               {"primitives", st.primitives},
               {"iou", number_or_null(st.iou)},
               {"evaluations", st.evaluations},
               {"trees", st.trees},
               {"seconds", number_or_null(st.seconds)},
               {"stop_reason", st.stop_reason}};
}

}  // namespace csgfit::json_detail
