// JSON form of a 3D fit ("dimension": 3); see to_json3d in fit3d.h.
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "csgfit/error.h"
#include "csgfit/fit3d.h"

namespace csgfit {

namespace {

using ojson = nlohmann::ordered_json;

double finite(double v, const std::string& where) {
  if (!std::isfinite(v)) throw InputError("JSON: " + where + ": a value is not a finite number");
  return v;
}

ojson node3d_to_json(const Node3D& n, const std::string& where) {
  if (!n.is_leaf()) {
    ojson children = ojson::array();
    for (std::size_t i = 0; i < n.children.size(); ++i)
      children.push_back(node3d_to_json(n.children[i], where + ".children[" + std::to_string(i) + "]"));
    const char* op = n.kind == NodeKind::Union ? "union"
                     : n.kind == NodeKind::Difference ? "difference" : "intersection";
    return ojson{{"op", op}, {"children", std::move(children)}};
  }
  const Primitive3D& p = n.primitive;
  const Vec3 e = p.rotation.euler_deg();
  ojson j;
  j["type"] = std::string(to_string(p.kind));
  j["center"] = {finite(p.cx, where), finite(p.cy, where), finite(p.cz, where)};
  j["rotation"] = {finite(p.rotation.w, where), finite(p.rotation.x, where),
                   finite(p.rotation.y, where), finite(p.rotation.z, where)};
  j["euler_deg"] = {finite(e[0], where), finite(e[1], where), finite(e[2], where)};
  const Vec3& d = p.dims;
  for (double v : d) finite(v, where);
  switch (p.kind) {
    case PrimitiveKind3D::Box: j["size"] = {d[0], d[1], d[2]}; break;
    case PrimitiveKind3D::Sphere: j["r"] = d[0]; break;
    case PrimitiveKind3D::Cylinder: j["r"] = d[0], j["h"] = d[2]; break;
    case PrimitiveKind3D::Cone: j["r1"] = d[0], j["r2"] = d[1], j["h"] = d[2]; break;
    case PrimitiveKind3D::Ellipsoid: j["radii"] = {d[0], d[1], d[2]}; break;
    case PrimitiveKind3D::Torus: j["R"] = d[0], j["r"] = d[1]; break;
    case PrimitiveKind3D::TriangularPrism:
      j["w"] = d[0], j["h"] = d[1], j["depth"] = d[2], j["apex"] = finite(p.apex, where);
      break;
  }
  return j;
}

ojson number_or_null(double v) { return std::isfinite(v) ? ojson(v) : ojson(nullptr); }

}  // namespace

std::string to_json3d(const FitResult3D& result, const VoxelGrid& grid, const std::string& source,
                      const Quaternion& frame) {
  const FitStats& st = result.stats;
  ojson doc;
  doc["schema"] = "csgfit/1";
  doc["dimension"] = 3;
  doc["units"] = "mm";
  doc["source"] = source;
  doc["grid"] = ojson{{"nx", grid.nx()},
                     {"ny", grid.ny()},
                     {"nz", grid.nz()},
                     {"origin", {grid.origin_x(), grid.origin_y(), grid.origin_z()}},
                     {"voxel_size", grid.voxel_size()},
                     {"frame", {frame.w, frame.x, frame.y, frame.z}}};
  doc["tree"] = node3d_to_json(result.tree, "tree");
  doc["stats"] = ojson{{"k", number_or_null(st.k)},
                       {"score", number_or_null(st.score)},
                       {"excess", st.excess},
                       {"uncovered", st.uncovered},
                       {"primitives", st.primitives},
                       {"iou", number_or_null(st.iou)},
                       {"evaluations", st.evaluations},
                       {"trees", st.trees},
                       {"seconds", number_or_null(st.seconds)},
                       {"stop_reason", st.stop_reason}};
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

}  // namespace csgfit
