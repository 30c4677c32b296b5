// JSON form of a 3D fit ("dimension": 3); see to_json3d in csgfit/io/json.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/io/json.h"
#include "io/json/json_fields.h"
#include "io/json/json_nurbs.h"
#include "io/json/json_sweeps.h"

namespace csgfit {

namespace {

using json_detail::fail;
using json_detail::finite_field;
using json_detail::kNotFinite3D;
using json_detail::ojson;

// "sweeps" when the tree has any: a document of a tree without one stays as it was.
void add_sweeps(const Node3D& tree, ojson& doc) {
  ojson sweeps = json_detail::sweeps_to_json(tree);
  if (!sweeps.empty()) doc["sweeps"] = std::move(sweeps);
}

double finite(double v, const std::string& where) {
  if (!std::isfinite(v)) fail(where, "a value is not a finite number");
  return v;
}

ojson node3d_to_json(const Node3D& n, const std::string& where) {
  if (!n.is_leaf()) {
    ojson children = ojson::array();
    for (std::size_t i = 0; i < n.children.size(); ++i)
      children.push_back(node3d_to_json(n.children[i], where + ".children[" + std::to_string(i) + "]"));
    return ojson{{"op", std::string(to_string(n.kind))}, {"children", std::move(children)}};
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
    case PrimitiveKind3D::Nurbs: json_detail::write_nurbs_fields(p, where, j); break;
    case PrimitiveKind3D::RoundedBox:
      j["size"] = {d[0], d[1], d[2]};
      j["corner"] = finite(p.corner, where);
      break;
  }
  if (p.is_polygonal()) j["sides"] = p.sides;
  return j;
}

// ---- reading (csgfit export) ---------------------------------------------------------------

double number(const ojson& j, const char* key, const std::string& where) {
  return json_detail::finite_number(j, key, where, kNotFinite3D);
}

// A polygonal cylinder's or cone's "sides": absent (round), or an integer in [3, kMaxSides].
int sides(const ojson& j, const Primitive3D& p, const std::string& where) {
  const auto it = j.find("sides");
  if (it == j.end()) return 0;
  if (p.kind != PrimitiveKind3D::Cylinder && p.kind != PrimitiveKind3D::Cone)
    fail(where, "'sides' is for cylinders and cones only");
  if (!it->is_number_integer() || it->get<long long>() < 3 ||
      it->get<long long>() > Primitive3D::kMaxSides)
    fail(where, "'sides' must be an integer from 3 to " + std::to_string(Primitive3D::kMaxSides));
  return it->get<int>();
}

// A rounded box's "corner": a number in (0, min(sx, sy) / 2], the bound by a hair of rounding
// (a stadium written in decimal).
double corner(const ojson& j, const Primitive3D& p, const std::string& where) {
  const double c = number(j, "corner", where);
  const double most = std::min(p.dims[0], p.dims[1]) / 2;
  if (!(c > 0) || c > most * (1 + 1e-12))
    fail(where, "'corner' must be > 0 and at most half the smaller of size x and size y");
  return std::min(c, most);
}

template <std::size_t N>
std::array<double, N> numbers(const ojson& j, const char* key, const std::string& where) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_array() || it->size() != N)
    fail(where, std::string("'") + key + "' must be an array of " + std::to_string(N) + " numbers");
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    if (!(*it)[i].is_number()) fail(where, std::string("'") + key + "' must hold numbers");
    out[i] = finite_field((*it)[i].get<double>(), where, key, kNotFinite3D);
  }
  return out;
}

Node3D node3d_from_json(const ojson& j, const std::string& where, int depth) {
  if (depth > 1000) fail(where, "the tree is nested too deeply");
  if (!j.is_object()) fail(where, "a node must be an object");
  if (const auto op = j.find("op"); op != j.end()) {
    const std::string name = op->is_string() ? op->get<std::string>() : "";
    NodeKind kind;
    if (!json_detail::node_kind_from_name(name, &kind)) fail(where, "unknown op '" + name + "'");
    const auto kids = j.find("children");
    if (kids == j.end() || !kids->is_array() || kids->empty())
      fail(where, "'children' must be a non-empty array");
    std::vector<Node3D> children;
    for (std::size_t i = 0; i < kids->size(); ++i)
      children.push_back(node3d_from_json((*kids)[i], where + ".children[" + std::to_string(i) + "]", depth + 1));
    return Node3D::op(kind, std::move(children));
  }
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) fail(where, "a node needs 'op' or 'type'");
  Primitive3D p;
  try {
    p.kind = primitive_kind3d_from_string(type->get<std::string>());
  } catch (const std::invalid_argument& e) {
    fail(where, e.what());
  }
  const auto c = numbers<3>(j, "center", where);
  p.cx = c[0], p.cy = c[1], p.cz = c[2];
  // The quaternion is what the writer keeps exactly; euler_deg is for people and OpenSCAD.
  if (j.contains("rotation")) {
    const auto q = numbers<4>(j, "rotation", where);
    p.rotation = Quaternion{q[0], q[1], q[2], q[3]};
  } else if (j.contains("euler_deg")) {
    const auto e = numbers<3>(j, "euler_deg", where);
    p.rotation = Quaternion::from_euler_deg(e[0], e[1], e[2]);
  }
  switch (p.kind) {
    case PrimitiveKind3D::Box: {
      const auto d = numbers<3>(j, "size", where);
      p.dims = {d[0], d[1], d[2]};
      break;
    }
    case PrimitiveKind3D::Sphere: {
      const double r = number(j, "r", where);
      p.dims = {r, r, r};
      break;
    }
    case PrimitiveKind3D::Cylinder: {
      const double r = number(j, "r", where);
      p.dims = {r, r, number(j, "h", where)};
      break;
    }
    case PrimitiveKind3D::Cone:
      p.dims = {number(j, "r1", where), number(j, "r2", where), number(j, "h", where)};
      break;
    case PrimitiveKind3D::Ellipsoid: {
      const auto d = numbers<3>(j, "radii", where);
      p.dims = {d[0], d[1], d[2]};
      break;
    }
    case PrimitiveKind3D::Torus: p.dims = {number(j, "R", where), number(j, "r", where), 0}; break;
    case PrimitiveKind3D::TriangularPrism:
      p.dims = {number(j, "w", where), number(j, "h", where), number(j, "depth", where)};
      p.apex = j.contains("apex") ? number(j, "apex", where) : 0;
      break;
    case PrimitiveKind3D::Nurbs: json_detail::read_nurbs_fields(j, where, p); break;
    case PrimitiveKind3D::RoundedBox: {
      const auto d = numbers<3>(j, "size", where);
      p.dims = {d[0], d[1], d[2]};
      break;
    }
  }
  p.sides = sides(j, p, where);
  for (double v : p.dims)
    if (v < 0 || (v == 0 && !(p.kind == PrimitiveKind3D::Cone || p.kind == PrimitiveKind3D::Torus)))
      fail(where, std::string(to_string(p.kind)) + " sizes must be > 0");
  if (p.kind == PrimitiveKind3D::RoundedBox)
    p.corner = corner(j, p, where);
  else if (j.contains("corner"))
    fail(where, "'corner' is for rounded boxes only");
  // Refused rather than repaired: a quaternion of length 0 has no rotation to mean.
  const double len = std::sqrt(p.rotation.w * p.rotation.w + p.rotation.x * p.rotation.x +
                               p.rotation.y * p.rotation.y + p.rotation.z * p.rotation.z);
  if (!(len > 1e-9)) fail(where, "'rotation' must be a non-zero quaternion [w, x, y, z]");
  p.rotation.normalize();
  return Node3D::leaf(p);
}

ojson parse(const std::string& text) {
  try {
    return ojson::parse(text);
  } catch (const ojson::exception& e) {  // parse errors, and numbers beyond a double (fuzz/)
    throw InputError(std::string("JSON: not valid JSON (") + e.what() + ")");
  }
}

bool is_3d(const ojson& doc) {
  if (!doc.is_object()) return false;
  const auto d = doc.find("dimension");
  return d != doc.end() && d->is_number_integer() && d->get<int>() == 3;
}

}  // namespace

bool is_json3d(const std::string& text) {
  try {
    return is_3d(ojson::parse(text));
  } catch (const ojson::exception&) {
    return false;
  }
}

Node3D from_json3d(const std::string& text, std::string* source) {
  const ojson doc = parse(text);
  if (!is_3d(doc)) throw InputError("JSON: not a 3D document ('dimension' must be 3)");
  if (const auto u = doc.find("units"); u != doc.end() && !(u->is_string() && *u == "mm"))
    throw InputError("JSON: 'units' must be \"mm\"");
  const auto tree = doc.find("tree");
  if (tree == doc.end()) throw InputError("JSON: missing 'tree'");
  if (source) {
    const auto src = doc.find("source");
    *source = src != doc.end() && src->is_string() ? src->get<std::string>() : "";
  }
  return node3d_from_json(*tree, "tree", 0);
}

std::string to_json3d(const FitResult3D& result, const VoxelGrid& grid, const std::string& source,
                      const Quaternion& frame) {
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
  doc["shared_dimensions"] = json_detail::shared_to_json(result.tree, 1.0);
  add_sweeps(result.tree, doc);
  doc["stats"] = json_detail::stats_to_json(result.stats);
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

std::string to_json_sweeps(const Node3D& tree) {
  return json_detail::sweeps_to_json(tree).dump(-1, ' ', false, ojson::error_handler_t::replace);
}

namespace {

ojson graph_to_json(const PrecedenceGraph& g) {
  ojson nodes = ojson::array(), arcs = ojson::array();
  for (std::size_t i = 0; i < g.nodes.size(); ++i) {
    const SignedPrimitive& n = g.nodes[i];
    const std::string where = "precedence_graph.nodes[" + std::to_string(i) + "]";
    nodes.push_back(ojson{{"kind", std::string(to_string(n.primitive.kind))},
                          {"sign", n.positive ? "positive" : "negative"},
                          {"conjectured", n.conjectured},
                          {"order", g.order[i]},
                          {"subobject", g.subobject[i]},
                          {"dims", {n.primitive.dims[0], n.primitive.dims[1], n.primitive.dims[2]}},
                          {"primitive", node3d_to_json(Node3D::leaf(n.primitive), where)},
                          {"patches", n.patches}});
  }
  for (const PrecedenceArc& a : g.arcs)
    arcs.push_back(ojson{{"from", a.from}, {"to", a.to},
                         {"kind", a.kind == ArcKind::Subtracting ? "subtracting" : "appending"}});
  return ojson{{"subobjects", g.subobjects}, {"nodes", std::move(nodes)}, {"arcs", std::move(arcs)}};
}

// What a fit to points (a range image's or a scan's) writes first: no grid, every source.
ojson points_document(const Node3D& tree, const FitStats& stats, const std::vector<std::string>& sources) {
  ojson doc;
  doc["schema"] = "csgfit/1";
  doc["dimension"] = 3;
  doc["units"] = "mm";
  doc["source"] = sources.empty() ? std::string() : sources.front();
  doc["sources"] = sources;
  doc["tree"] = node3d_to_json(tree, "tree");
  doc["shared_dimensions"] = json_detail::shared_to_json(tree, 1.0);
  add_sweeps(tree, doc);
  doc["stats"] = json_detail::stats_to_json(stats);
  return doc;
}

}  // namespace

std::string to_json_range(const RangeFitResult& result, const std::vector<std::string>& sources) {
  ojson doc = points_document(result.tree, result.stats, sources);
  ojson views = ojson::array();
  for (const ViewAgreement& v : result.views)
    views.push_back(ojson{{"source", v.source}, {"silhouette_iou", v.silhouette_iou},
                          {"depth_error", v.depth_error}});
  doc["views"] = std::move(views);
  doc["precedence_graph"] = graph_to_json(result.graph);
  ojson patches = ojson::array();
  for (const SurfacePatch& p : result.patches)
    patches.push_back(ojson{{"kind", std::string(to_string(p.kind))}, {"points", p.points.size()},
                            {"convex", p.convex}, {"rms", p.rms}});
  doc["patches"] = std::move(patches);
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

std::string to_json_points(const PointsFitResult& result, const std::vector<std::string>& sources) {
  ojson doc = points_document(result.tree, result.stats, sources);
  const FitnessTerms& f = result.terms;
  doc["points"] = ojson{{"scan", result.scan == ScanKind::Top ? "top" : "all"},
                        {"count", result.points},
                        {"search", result.islands > 0 ? "gp" : "hill"},
                        {"islands", result.islands},
                        {"generations", result.generations},
                        {"first_tree", result.first_tree},
                        {"fitness", f.fitness},
                        {"distance_term", f.distance},
                        {"normals_term", f.normals},
                        {"curvature_term", f.curvature},
                        {"floor_term", f.floor},
                        {"mean_distance", f.mean_distance},
                        {"nodes", f.nodes},
                        {"patch_rms", result.patch_rms}};
  return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

}  // namespace csgfit
