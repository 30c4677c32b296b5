// The optimised tree back as OpenSCAD text: every leaf is its own call under its world
// placement, as translate / rotate / scale where the matrix is one, else multmatrix.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "csgfit/io/openscad_program.h"
#include "matrix4.h"

namespace csgfit {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

std::string number(double v) {
  if (std::abs(v) < 1e-12) v = 0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string vec3(double a, double b, double c) { return "[" + number(a) + ", " + number(b) + ", " + number(c) + "]"; }

std::string multmatrix(const Matrix4& m) {
  std::string s = "multmatrix([";
  for (int i = 0; i < 4; ++i) {
    s += i ? ", [" : "[";
    for (int j = 0; j < 4; ++j) s += (j ? ", " : "") + number(m[4 * i + j]);
    s += "]";
  }
  return s + "])";
}

// OpenSCAD's rotate([x, y, z]) = Rz(z) Ry(y) Rx(x).
Matrix4 rotation(double ax, double ay, double az) {
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay), cz = std::cos(az), sz = std::sin(az);
  return {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx, 0, sz * cy, sz * sy * sx + cz * cx,
          sz * sy * cx - cz * sx, 0, -sy, cy * sx, cy * cx, 0, 0, 0, 0, 1};
}

// translate(t) rotate(r) scale(s), when the matrix is exactly that (no shear, no mirror).
std::string readable_placement(const Matrix4& m) {
  double s[3];
  for (int j = 0; j < 3; ++j) s[j] = std::sqrt(m[j] * m[j] + m[4 + j] * m[4 + j] + m[8 + j] * m[8 + j]);
  Matrix4 r = m;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) r[4 * i + j] /= s[j];
  const double ay = std::asin(std::max(-1.0, std::min(1.0, -r[8])));
  double ax = std::atan2(r[9], r[10]), az = std::atan2(r[4], r[0]);
  if (std::abs(std::cos(ay)) < 1e-9) ax = 0, az = std::atan2(-r[1], r[5]);
  const Matrix4 back = rotation(ax, ay, az);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::abs(back[4 * i + j] * s[j] - m[4 * i + j]) > 1e-9 * (1 + s[j])) return multmatrix(m) + " ";
  std::string out;
  if (std::abs(m[3]) + std::abs(m[7]) + std::abs(m[11]) > 0) out += "translate(" + vec3(m[3], m[7], m[11]) + ") ";
  if (std::abs(ax) + std::abs(ay) + std::abs(az) > 1e-12) out += "rotate(" + vec3(ax * kDeg, ay * kDeg, az * kDeg) + ") ";
  if (std::abs(s[0] - 1) + std::abs(s[1] - 1) + std::abs(s[2] - 1) > 1e-12) out += "scale(" + vec3(s[0], s[1], s[2]) + ") ";
  return out;
}

// Re-indents a call's own lines (a call with children spans several) under `pad`.
std::string indented(const std::string& call, const std::string& pad) {
  std::string out;
  for (char ch : call) {
    out += ch;
    if (ch == '\n') out += pad;
  }
  if (out.empty() || (out.back() != ';' && out.back() != '}')) out += ";";
  return out;
}

// A leaf's call under its placement. A .csg gets multmatrix with braces, the form every reader
// of the format takes (FreeCAD's importCSG needs the braces); a .scad the readable transforms.
void write_leaf(std::ostringstream& o, const ScadLeaf& leaf, const std::string& pad, bool csg_style) {
  if (scadm::is_identity(leaf.matrix)) {
    o << pad << indented(leaf.call, pad) << "\n";
  } else if (csg_style) {
    o << pad << multmatrix(leaf.matrix) << " {\n" << pad << "  " << indented(leaf.call, pad + "  ") << "\n"
      << pad << "}\n";
  } else {
    o << pad << readable_placement(leaf.matrix) << indented(leaf.call, pad) << "\n";
  }
}

// A centred cube around every halfspace, `scale` times their bounds: what ~X is cut from.
std::string universe_cube(const ScadProgram& p, double scale, bool csg) {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (std::size_t i = 0; i < p.halfspaces3.size() + p.halfspaces2.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      const bool two = i >= p.halfspaces3.size();
      if (two && a == 2) continue;
      const double l = two ? p.halfspaces2[i - p.halfspaces3.size()].bounds.lo[a] : p.halfspaces3[i].bounds.lo[a];
      const double h = two ? p.halfspaces2[i - p.halfspaces3.size()].bounds.hi[a] : p.halfspaces3[i].bounds.hi[a];
      lo[a] = i ? std::min(lo[a], l) : l, hi[a] = i ? std::max(hi[a], h) : h;
    }
  }
  double c[3], s[3];
  for (int a = 0; a < 3; ++a) c[a] = (lo[a] + hi[a]) / 2, s[a] = scale * (hi[a] - lo[a]) + 1;
  Matrix4 shift = scadm::identity();
  shift[3] = c[0], shift[7] = c[1], shift[11] = p.dimension == 3 ? c[2] : 0;
  const std::string box = p.dimension == 2 ? "square(size = [" + number(s[0]) + ", " + number(s[1]) + "], center = true);"
                                           : "cube(size = " + vec3(s[0], s[1], s[2]) + ", center = true);";
  return csg ? multmatrix(shift) + " { " + box + " }" : readable_placement(shift) + box;
}

struct Writer {
  const ScadProgram& p;
  bool csg;
  std::string universe;
  void node(std::ostringstream& o, const opt::Expr& e, const std::string& pad) const;
};

void Writer::node(std::ostringstream& o, const opt::Expr& e, const std::string& pad) const {
  using opt::ExprOp;
  switch (e.op) {
    case ExprOp::Complement:
      o << pad << "difference() {\n" << pad << "  " << universe << "\n";
      node(o, e.kids[0], pad + "  ");
      o << pad << "}\n";
      return;
    case ExprOp::Halfspace: return write_leaf(o, p.leaves.at(static_cast<std::size_t>(e.index)), pad, csg);
    case ExprOp::Opaque: return write_leaf(o, p.opaque.at(static_cast<std::size_t>(e.index)), pad, csg);
    case ExprOp::Union:
    case ExprOp::Intersection:
    case ExprOp::Difference: {
      const char* name = e.op == ExprOp::Union ? "union" : e.op == ExprOp::Intersection ? "intersection" : "difference";
      o << pad << name << "() {\n";
      for (const opt::Expr& k : e.kids) node(o, k, pad + "  ");
      o << pad << "}\n";
      return;
    }
    default: throw std::logic_error("write_openscad_program: the tree still has " + opt::to_text(e));
  }
}

}  // namespace

std::string write_openscad_program(const ScadProgram& program, const opt::Expr& tree, const ScadWriteOptions& options) {
  std::ostringstream o;
  std::istringstream header(options.header);
  for (std::string line; std::getline(header, line);) o << "// " << line << "\n";
  const Writer writer{program, options.csg_style, universe_cube(program, options.universe_scale, options.csg_style)};
  writer.node(o, tree, "");
  return o.str();
}

}  // namespace csgfit
