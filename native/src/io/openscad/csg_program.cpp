// OpenSCAD's CSG calls to the optimiser's expression: booleans become operators, multmatrix
// folds into the leaves' matrices, group / color / render are unions of their children, and
// whatever has no inside test here is an opaque leaf that keeps its text.
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <unordered_map>

#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"
#include "csgfit/optimise/sample_set.h"
#include "io/input_file.h"
#include "matrix4.h"
#include "shapes.h"

namespace csgfit {
namespace {

using opt::Expr;
using opt::ExprOp;

Matrix4 multmatrix_of(const ScadCall& c, const std::string& where) {
  const ScadValue* m = c.argument("m");
  if (!m && !c.arguments.empty()) m = &c.arguments[0].second;
  if (!m || m->type != ScadValue::Type::Vector || m->items.size() < 3)
    throw InputError(where + ": multmatrix without a 4 x 4 matrix");
  Matrix4 out = scadm::identity();
  for (std::size_t i = 0; i < std::min<std::size_t>(4, m->items.size()); ++i) {
    const ScadValue& row = m->items[i];
    if (row.type != ScadValue::Type::Vector || row.items.size() < 4)
      throw InputError(where + ": multmatrix row " + std::to_string(i + 1) + " is not 4 numbers");
    for (std::size_t j = 0; j < 4; ++j) {
      if (row.items[j].type != ScadValue::Type::Number || !std::isfinite(row.items[j].number))
        throw InputError(where + ": multmatrix has a value that is not a finite number");
      out[4 * i + j] = row.items[j].number;
    }
  }
  if (std::abs(out[12]) + std::abs(out[13]) + std::abs(out[14]) + std::abs(out[15] - 1) > 1e-12)
    throw InputError(where + ": multmatrix is projective (its last row is not 0 0 0 1)");
  if (!(std::abs(scadm::det3(out)) > 1e-12))
    throw InputError(where + ": multmatrix is singular (it flattens its children)");
  return out;
}

// The numbers of a vector argument (or one number as {v, v, v} when `scalar` allows it).
std::array<double, 3> vector_arg(const ScadCall& c, const char* name, std::array<double, 3> fallback, bool scalar,
                                 const std::string& where) {
  const ScadValue* v = c.argument(name);
  if (!v && !c.arguments.empty() && c.arguments[0].first.empty()) v = &c.arguments[0].second;
  if (!v) return fallback;
  if (scalar && v->type == ScadValue::Type::Number) return {v->number, v->number, v->number};
  if (v->type != ScadValue::Type::Vector) throw InputError(where + ": " + c.name + "'s " + name + " is not a vector");
  std::array<double, 3> out{0, 0, 0};
  for (std::size_t i = 0; i < std::min<std::size_t>(3, v->items.size()); ++i) {
    if (v->items[i].type != ScadValue::Type::Number) throw InputError(where + ": " + c.name + "'s " + name + " is not numbers");
    out[i] = v->items[i].number;
  }
  return out;
}

Matrix4 rotation_about(int axis, double degrees) {
  const double r = degrees * 3.14159265358979323846 / 180, co = std::cos(r), si = std::sin(r);
  Matrix4 m = scadm::identity();
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  m[4 * a + a] = co, m[4 * a + b] = -si, m[4 * b + a] = si, m[4 * b + b] = co;
  return m;
}

// translate / rotate / scale / mirror, as a hand-written program (or our .scad) has them; a
// flattened .csg has only multmatrix.
std::optional<Matrix4> transform_of(const ScadCall& c, const std::string& where) {
  Matrix4 m = scadm::identity();
  if (c.name == "translate") {
    const auto t = vector_arg(c, "v", {0, 0, 0}, false, where);
    m[3] = t[0], m[7] = t[1], m[11] = t[2];
  } else if (c.name == "scale") {
    const auto s = vector_arg(c, "v", {1, 1, 1}, true, where);
    m[0] = s[0], m[5] = s[1], m[10] = s[2];
  } else if (c.name == "rotate") {
    const ScadValue* a = c.argument("a");
    if (!a && !c.arguments.empty()) a = &c.arguments[0].second;
    if (c.argument("v") || (a && a->type == ScadValue::Type::Number)) {
      const double deg = a && a->type == ScadValue::Type::Number ? a->number : 0;
      const auto v = c.argument("v") ? vector_arg(c, "v", {0, 0, 1}, false, where) : std::array<double, 3>{0, 0, 1};
      const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (!(n > 0)) return m;
      const double r = deg * 3.14159265358979323846 / 180, co = std::cos(r), si = std::sin(r);
      const double x = v[0] / n, y = v[1] / n, z = v[2] / n, t = 1 - co;
      m = {t * x * x + co, t * x * y - si * z, t * x * z + si * y, 0, t * x * y + si * z, t * y * y + co,
           t * y * z - si * x, 0, t * x * z - si * y, t * y * z + si * x, t * z * z + co, 0, 0, 0, 0, 1};
    } else {
      const auto e = vector_arg(c, "a", {0, 0, 0}, false, where);
      m = scadm::multiply(rotation_about(2, e[2]), scadm::multiply(rotation_about(1, e[1]), rotation_about(0, e[0])));
    }
  } else if (c.name == "mirror") {
    const auto v = vector_arg(c, "v", {1, 0, 0}, false, where);
    const double n2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (!(n2 > 0)) return m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[4 * i + j] = (i == j) - 2 * v[i] * v[j] / n2;
  } else {
    return std::nullopt;
  }
  if (!(std::abs(scadm::det3(m)) > 1e-12)) throw InputError(where + ": " + c.name + " is singular (it flattens its children)");
  return m;
}

// Walks the calls of one dimension (3 or 2), building the expression and its leaves.
template <std::size_t D>
struct Builder {
  std::string_view text;
  std::string file;
  opt::HalfspaceList<D> halfspaces;
  std::vector<ScadLeaf> leaves, opaque;
  std::size_t operations = 0;
  std::unordered_map<std::string, int> index_of;

  std::string where(const ScadCall& c) const { return file + ":" + std::to_string(c.line); }

  std::string call_text(const ScadCall& c) const {
    return std::string(text.substr(c.source_begin, c.source_end - c.source_begin));
  }

  Expr children(const ScadCall& c, const Matrix4& m, ExprOp op) {
    std::vector<Expr> kids;
    for (const ScadCall& k : c.children) {
      Expr e = call(k, m);
      kids.push_back(std::move(e));
    }
    if (kids.empty()) return Expr::empty();
    if (kids.size() == 1 && op != ExprOp::Difference) return std::move(kids[0]);
    return Expr::make(op, std::move(kids));
  }

  // The same call under the same matrix is the same halfspace (one index), so that the
  // structural rules see copies as identical operands.
  Expr leaf(const ScadCall& c, const Matrix4& m, opt::Halfspace<D> h) {
    std::string key = call_text(c);
    key.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * m.size());
    const auto [at, fresh] = index_of.emplace(std::move(key), static_cast<int>(halfspaces.size()));
    if (!fresh) return Expr::halfspace(at->second);
    if (halfspaces.size() >= opt::kMaxHalfspaces)  // refused while reading, before it costs more
      throw InputError(file + ": the program has more than " + std::to_string(opt::kMaxHalfspaces) +
                       " distinct primitives; optimize takes at most " + std::to_string(opt::kMaxHalfspaces));
    halfspaces.push_back(std::move(h));
    leaves.push_back({m, call_text(c), c.line});
    return Expr::halfspace(static_cast<int>(halfspaces.size() - 1));
  }

  Expr opaque_leaf(const ScadCall& c, const Matrix4& m) {
    opaque.push_back({m, call_text(c), c.line});
    return Expr::opaque(static_cast<int>(opaque.size() - 1));
  }

  Expr call(const ScadCall& c, const Matrix4& m);
};

// The 2D solid under an extrusion, or null when it holds something opaque.
std::shared_ptr<scad_shapes::Solid2D> section_of(const ScadCall& c, std::string_view text, const std::string& file) {
  Builder<2> b{text, file, {}, {}, {}, 0, {}};
  auto solid = std::make_shared<scad_shapes::Solid2D>();
  solid->tree = b.children(c, scadm::identity(), ExprOp::Union);
  if (!b.opaque.empty() || b.halfspaces.empty()) return nullptr;
  solid->halfspaces = std::move(b.halfspaces);
  return solid;
}

template <std::size_t D>
Expr Builder<D>::call(const ScadCall& c, const Matrix4& m) {
  const std::string& n = c.name;
  if (n == "union" || n == "group" || n == "color" || n == "render") {
    operations += n == "union";
    return children(c, m, ExprOp::Union);
  }
  if (n == "difference" || n == "intersection") {
    ++operations;
    Expr e = children(c, m, n == "difference" ? ExprOp::Difference : ExprOp::Intersection);
    return e;
  }
  if (n == "multmatrix") return children(c, scadm::multiply(m, multmatrix_of(c, where(c))), ExprOp::Union);
  if (auto t = transform_of(c, where(c))) return children(c, scadm::multiply(m, *t), ExprOp::Union);
  if constexpr (D == 3) {
    if (auto h = scad_shapes::primitive3(c, m, where(c))) return leaf(c, m, std::move(*h));
    if (scad_shapes::is_extrusion(n)) {
      if (auto section = section_of(c, text, file)) return leaf(c, m, scad_shapes::extrusion(c, section, m, where(c)));
    }
  } else {
    if (auto h = scad_shapes::primitive2(c, m, where(c))) return leaf(c, m, std::move(*h));
  }
  return opaque_leaf(c, m);
}

// 2 when the first primitive found (depth first, outside extrusions) is a 2D one.
int dimension_of(const std::vector<ScadCall>& calls) {
  for (const ScadCall& c : calls) {
    if (scad_shapes::is_3d_primitive(c.name) || scad_shapes::is_extrusion(c.name) || c.name == "polyhedron") return 3;
    if (scad_shapes::is_2d_primitive(c.name) || c.name == "text") return 2;
    if (int d = dimension_of(c.children)) return d;
  }
  return 0;
}

}  // namespace

ScadProgram program_from_csg(const std::vector<ScadCall>& calls, std::string_view text, const std::string& file) {
  ScadProgram p;
  p.dimension = dimension_of(calls);
  if (p.dimension == 0) throw InputError(file + ": the program has no primitives");
  ScadCall top;
  top.name = "group";
  top.children = calls;
  auto finish = [&](auto& b) {
    p.tree = b.children(top, scadm::identity(), ExprOp::Union);
    p.leaves = std::move(b.leaves);
    p.opaque = std::move(b.opaque);
    p.operations = b.operations;
  };
  if (p.dimension == 3) {
    Builder<3> b{text, file, {}, {}, {}, 0, {}};
    finish(b);
    p.halfspaces3 = std::move(b.halfspaces);
  } else {
    Builder<2> b{text, file, {}, {}, {}, 0, {}};
    finish(b);
    p.halfspaces2 = std::move(b.halfspaces);
  }
  if (p.leaves.empty() && p.opaque.empty()) throw InputError(file + ": the program has no primitives");
  return p;
}

// Primitive calls in the text, counted before parsing (a parsed call takes a few hundred bytes).
std::size_t primitive_calls(const std::string& text) {
  std::size_t n = 0;
  for (const char* name : {"cube", "sphere", "cylinder", "polyhedron", "circle", "square", "polygon"}) {
    const std::string call = std::string(name) + "(";
    for (std::size_t at = text.find(call); at != std::string::npos; at = text.find(call, at + call.size())) ++n;
  }
  return n;
}

constexpr std::size_t kMaxPrimitiveCalls = 200000;

ScadProgram read_openscad_program(const std::string& path) {
  const bool scad = path.size() >= 5 && (path.compare(path.size() - 5, 5, ".scad") == 0 ||
                                         path.compare(path.size() - 5, 5, ".SCAD") == 0);
  const std::string text = scad ? flatten_scad_with_openscad(path) : io_detail::read_whole_file(path, 512LL << 20, "too large for a CSG program", io_detail::FileContent::Text);
  if (const std::size_t n = primitive_calls(text); n > kMaxPrimitiveCalls)
    throw InputError(path + ": the program has " + std::to_string(n) + " primitive calls; optimize reads at most " +
                     std::to_string(kMaxPrimitiveCalls));
  // The parsed calls take some tens of bytes per byte of text (numbers become values).
  check_allocation(48.0 * static_cast<double>(text.size()), "the parsed CSG program");
  const std::vector<ScadCall> calls = parse_openscad_csg(text, path);
  return program_from_csg(calls, text, path);
}

}  // namespace csgfit
