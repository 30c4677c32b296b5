#include <algorithm>
#include <cmath>

#include "csgfit/error.h"
#include "csgfit/io/openscad_program.h"
#include "csgfit/optimise/tree_expression.h"
#include "matrix4.h"

namespace csgfit {
namespace {

double arg_or(const ScadCall& c, const char* name, double fallback) {
  const ScadValue* v = c.argument(name);
  return v && v->type == ScadValue::Type::Number ? v->number : fallback;
}

// The placement as rotation and per-axis scale, or false when it shears or mirrors.
bool rotation_and_scale(const Matrix4& m, Quaternion& q, Vec3& s) {
  Mat3 r{};
  for (int j = 0; j < 3; ++j) {
    s[j] = std::sqrt(m[j] * m[j] + m[4 + j] * m[4 + j] + m[8 + j] * m[8 + j]);
    for (int i = 0; i < 3; ++i) r[i][j] = m[4 * i + j] / s[j];
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      if (std::abs(r[0][a] * r[0][b] + r[1][a] * r[1][b] + r[2][a] * r[2][b]) > 1e-9) return false;
  if (scadm::det3(m) <= 0) return false;
  q = quaternion_from_matrix(r);
  return true;
}

Primitive3D primitive_of(const ScadLeaf& leaf) {
  const std::string where = "line " + std::to_string(leaf.line);
  const std::vector<ScadCall> calls = parse_openscad_csg(leaf.call, where);
  const ScadCall& c = calls.at(0);
  Quaternion q;
  Vec3 s{};
  if (!rotation_and_scale(leaf.matrix, q, s))
    throw InputError(where + ": " + c.name + " is sheared or mirrored; write .scad or .csg, which keep it");
  const auto at = [&](double x, double y, double z) { return scadm::apply(leaf.matrix, x, y, z); };
  const bool centred = c.argument("center") && c.argument("center")->type == ScadValue::Type::Bool &&
                       c.argument("center")->boolean;
  if (c.name == "cube") {
    Vec3 size{1, 1, 1};
    if (const ScadValue* v = c.argument("size"); v && v->type == ScadValue::Type::Vector && v->items.size() == 3)
      size = {v->items[0].number, v->items[1].number, v->items[2].number};
    else if (v && v->type == ScadValue::Type::Number)
      size = {v->number, v->number, v->number};
    const auto p = centred ? at(0, 0, 0) : at(size[0] / 2, size[1] / 2, size[2] / 2);
    return Primitive3D::box(p[0], p[1], p[2], size[0] * s[0], size[1] * s[1], size[2] * s[2], q);
  }
  if (c.name == "sphere") {
    const double r = arg_or(c, "r", 1);
    const auto p = at(0, 0, 0);
    if (std::abs(s[0] - s[1]) < 1e-9 * s[0] && std::abs(s[0] - s[2]) < 1e-9 * s[0]) return Primitive3D::sphere(p[0], p[1], p[2], r * s[0]);
    return Primitive3D::ellipsoid(p[0], p[1], p[2], r * s[0], r * s[1], r * s[2], q);
  }
  if (c.name == "cylinder" && std::abs(s[0] - s[1]) < 1e-9 * s[0]) {
    const double h = arg_or(c, "h", 1), r = arg_or(c, "r", 1);
    const double r1 = arg_or(c, "r1", r), r2 = arg_or(c, "r2", r);
    const auto p = at(0, 0, centred ? 0 : h / 2);
    if (std::abs(r1 - r2) < 1e-12) return Primitive3D::cylinder(p[0], p[1], p[2], r1 * s[0], h * s[2], q);
    return Primitive3D::cone(p[0], p[1], p[2], r1 * s[0], r2 * s[0], h * s[2], q);
  }
  throw InputError(where + ": " + c.name + " has no csgfit primitive; write .scad or .csg, which keep it");
}

}  // namespace

Node3D node3d_of(const ScadProgram& program, const opt::Expr& tree) {
  if (program.dimension != 3) throw InputError("a 2D OpenSCAD program is written as .scad or .csg only");
  if (has_opaque(tree)) {
    throw InputError("the tree keeps an opaque call (line " + std::to_string(program.opaque.at(0).line) +
                     "); write .scad or .csg, which keep it");
  }
  const std::vector<int> used = opt::halfspaces_used(tree);
  std::vector<Primitive3D> leaves;
  for (const ScadLeaf& leaf : program.leaves) {
    try {
      leaves.push_back(primitive_of(leaf));
    } catch (const InputError&) {
      if (std::binary_search(used.begin(), used.end(), static_cast<int>(leaves.size()))) throw;
      leaves.push_back(Primitive3D{});  // not in the tree: never written
    }
  }
  return opt::tree_of(tree, leaves);
}

}  // namespace csgfit
