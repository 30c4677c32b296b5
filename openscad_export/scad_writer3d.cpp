#include "scad_writer3d.h"

#include "csgfit/model/interpolate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "scad_format.h"
#include "scad_patch.h"
#include "scad_tree_writer.h"

namespace csgfit {

namespace {

// The writers' shared helpers (scad_format.h, scad_tree_writer.h).
using namespace scad;

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;


/// A morph's turn of one primitive: R(axis, t * degrees) after its rotation at A.
struct Turn {
  Vec3 axis{0, 0, 1};
  double degrees = 0;
};

class Writer : public TreeWriter<Writer, Node3D> {
 public:
  Writer(int decimals, double extent) : decimals_(decimals), extent_(extent) {}
  /// One end of a morph: sizes may be 0, and each primitive turns by `turns` (pre-order) on top
  /// of its rotation (which the caller makes A's at both ends); `at_b` says which end.
  Writer(int decimals, double extent, const std::vector<Turn>* turns, bool at_b)
      : decimals_(decimals), extent_(extent), turns_(turns), at_b_(at_b) {}

  std::string primitive(const Primitive3D& p);

  bool uses_spheres() const { return spheres_; }
  bool uses_circles() const { return circles_; }
  bool uses_tori() const { return tori_; }
  bool uses_corners() const { return corners_; }
  /// Modules the body calls (one polyhedron per NURBS terminal) and the header lines saying
  /// how far each strays from its exact patch.
  const std::string& modules() const { return modules_; }
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  friend class TreeWriter<Writer, Node3D>;

  static std::string plural(PrimitiveKind3D k) {
    switch (k) {
      case PrimitiveKind3D::Box: return "boxes";
      case PrimitiveKind3D::Sphere: return "spheres";
      case PrimitiveKind3D::Cylinder: return "cylinders";
      case PrimitiveKind3D::Cone: return "cones";
      case PrimitiveKind3D::Ellipsoid: return "ellipsoids";
      case PrimitiveKind3D::Torus: return "tori";
      case PrimitiveKind3D::TriangularPrism: return "prisms";
      case PrimitiveKind3D::Nurbs: return "NURBS patches";
      case PrimitiveKind3D::RoundedBox: return "rounded boxes";
    }
    return "primitives";
  }
  int decimals() const { return decimals_; }

  static double check(double v, const char* what, const std::string& prim) {
    if (!std::isfinite(v) || std::fabs(v) > kMaxMagnitude)
      throw InputError("cannot write .scad: " + prim + " has a non-finite or out-of-range " +
                       what);
    return v;
  }
  double check_size(double v, const char* what, const std::string& prim) const {
    check(v, what, prim);
    if (!(v > 0) && !(turns_ && v == 0))
      throw InputError("cannot write .scad: " + prim + " has a " + what + " <= 0");
    return v;
  }

  // A morph's turn of this primitive, before its own rotation: "" when it does not turn.
  std::string turn(Tab& tab, const std::string& prefix) {
    if (!turns_) return "";
    const Turn& t = (*turns_)[static_cast<std::size_t>(count_ - 1)];
    if (number(t.degrees, 6) == "0") return "";
    const std::string a = add(tab, prefix, "turn", at_b_ ? t.degrees : 0.0, "[-180:0.1:180]", 6);
    return "rotate(a = " + a + ", v = [" + number(t.axis[0], 9) + ", " + number(t.axis[1], 9) +
           ", " + number(t.axis[2], 9) + "]) ";
  }

  double step() const { return slider_step(extent_); }
  std::string length_range(double v) const {
    return "[0:" + number(step(), 12) + ":" + number(nice_ceiling(std::max(extent_, std::fabs(v))), 12) +
           "]";
  }
  std::string position_range(double v) const {
    const double hi = nice_ceiling(std::max(extent_, std::fabs(v)));
    return "[" + number(-hi, 12) + ":" + number(step(), 12) + ":" + number(hi, 12) + "]";
  }

  std::string length(Tab& tab, const std::string& prefix, const char* field, double v) {
    return add(tab, prefix, field, v, length_range(v), decimals_);
  }
  // A length, or the shared parameter that stands for p's `shared` field.
  std::string length(Tab& tab, const Primitive3D& p, DimensionField shared,
                     const std::string& prefix, const char* field, double v) {
    if (const std::string* name = shared_name(p, shared)) return *name;
    return length(tab, prefix, field, v);
  }

  // The radius a cylinder or cone is drawn with: a round one's is sized by fn_r so that its
  // $fn-gon keeps the fitted area; a polygonal one is that polygon already, drawn as it is.
  std::string drawn_radius(const Primitive3D& p, const std::string& radius) {
    if (p.is_polygonal()) return radius;
    circles_ = true;
    return "fn_r(" + radius + ")";
  }
  // ", $fn = <its sides parameter>" for a polygonal cylinder or cone, "" for a round one (the
  // file's $fn draws it).
  std::string polygon_sides(Tab& tab, const std::string& prefix, const Primitive3D& p) {
    if (!p.is_polygonal()) return "";
    const std::string range = "[3:1:" + std::to_string(std::max(p.sides, 64)) + "]";
    return ", $fn = " + add(tab, prefix, "sides", p.sides, range, 0);
  }

  // "rotate([a, b, c]) " with a variable per non-zero angle, or "" for no rotation.
  std::string rotation(Tab& tab, const std::string& prefix, const Primitive3D& p,
                       const std::string& what) {
    Vec3 e;
    if (is_axially_symmetric(p)) {
      // Only the axis matters: rotate([a, b, 0]) takes local z to the axis (x, y, z) when
      // a = -asin(y), b = atan2(x, z).
      const Mat3 m = p.rotation.matrix();
      const double ax = m[0][2], ay = m[1][2], az = m[2][2];
      e = {-std::asin(std::clamp(ay, -1.0, 1.0)) * kRadToDeg, std::atan2(ax, az) * kRadToDeg, 0};
    } else {
      e = p.rotation.euler_deg();
    }
    static const char* const names[3] = {"rot_x", "rot_y", "rot_z"};
    std::string parts[3];
    bool any = false;
    for (int i = 0; i < 3; ++i) {
      check(e[i], "rotation", what);
      // Angles get more decimals than lengths: a degree turns a 100 mm part's end by 1.7 mm.
      if (number(e[i], 6) == "0") {
        parts[i] = "0";
        continue;
      }
      any = true;
      parts[i] = add(tab, prefix, names[i], e[i], "[-180:0.1:180]", 6);
    }
    if (!any) return "";
    return "rotate([" + parts[0] + ", " + parts[1] + ", " + parts[2] + "]) ";
  }

  int decimals_;
  double extent_;
  const std::vector<Turn>* turns_ = nullptr;
  bool at_b_ = false;
  bool spheres_ = false, circles_ = false, tori_ = false, corners_ = false;
  std::string modules_;
  std::vector<std::string> notes_;

  std::string nurbs(const Primitive3D& p, const std::string& prefix, const std::string& what);
  std::string rounded_box(Tab& tab, const Primitive3D& p, const std::string& prefix,
                          const std::string& what);
};

std::string Writer::primitive(const Primitive3D& p) {
  ++count_;
  numbered(p);
  const std::string num = std::to_string(count_);
  std::string prefix, title;
  switch (p.kind) {
    case PrimitiveKind3D::Box: prefix = "box_", title = "Box "; break;
    case PrimitiveKind3D::Sphere: prefix = "sphere_", title = "Sphere "; break;
    case PrimitiveKind3D::Cylinder: prefix = "cyl_", title = "Cylinder "; break;
    case PrimitiveKind3D::Cone: prefix = "cone_", title = "Cone "; break;
    case PrimitiveKind3D::Ellipsoid: prefix = "ellipsoid_", title = "Ellipsoid "; break;
    case PrimitiveKind3D::Torus: prefix = "torus_", title = "Torus "; break;
    case PrimitiveKind3D::TriangularPrism: prefix = "prism_", title = "Prism "; break;
    case PrimitiveKind3D::Nurbs: prefix = "nurbs_", title = "NURBS patch "; break;
    case PrimitiveKind3D::RoundedBox: prefix = "rbox_", title = "Rounded box "; break;
  }
  prefix += num;
  title += num;
  const std::string what = "primitive " + num + " (" + std::string(to_string(p.kind)) + ")";
  Tab tab{title, {}};
  const int d = decimals_;
  const std::string vx = add(tab, prefix, "cx", check(p.cx, "centre x", what), position_range(p.cx), d);
  const std::string vy = add(tab, prefix, "cy", check(p.cy, "centre y", what), position_range(p.cy), d);
  const std::string vz = add(tab, prefix, "cz", check(p.cz, "centre z", what), position_range(p.cz), d);
  const Vec3& s = p.dims;
  std::string code = "translate([" + vx + ", " + vy + ", " + vz + "]) ";
  if (p.kind != PrimitiveKind3D::Sphere) code += turn(tab, prefix) + rotation(tab, prefix, p, what);
  switch (p.kind) {
    case PrimitiveKind3D::Box: {
      const std::string a = length(tab, prefix, "size_x", check_size(s[0], "size x", what));
      const std::string b = length(tab, prefix, "size_y", check_size(s[1], "size y", what));
      const std::string c = length(tab, prefix, "size_z", check_size(s[2], "size z", what));
      code += "cube([" + a + ", " + b + ", " + c + "], center = true);";
      break;
    }
    case PrimitiveKind3D::Sphere: {
      const std::string r =
          length(tab, p, DimensionField::Radius, prefix, "r", check_size(s[0], "radius", what));
      code += "sphere(r = fn_sr(" + r + "));";
      spheres_ = true;
      break;
    }
    case PrimitiveKind3D::Cylinder: {
      const std::string r =
          length(tab, p, DimensionField::Radius, prefix, "r", check_size(s[0], "radius", what));
      const std::string h =
          length(tab, p, DimensionField::Length, prefix, "h", check_size(s[2], "height", what));
      code += "cylinder(h = " + h + ", r = " + drawn_radius(p, r) + ", center = true" +
              polygon_sides(tab, prefix, p) + ");";
      break;
    }
    case PrimitiveKind3D::Cone: {
      check(s[0], "bottom radius", what);
      check(s[1], "top radius", what);
      if (s[0] < 0 || s[1] < 0 || (!turns_ && !(std::max(s[0], s[1]) > 0)))
        throw InputError("cannot write .scad: " + what + " has a negative or zero radius");
      const std::string r1 = length(tab, prefix, "r1", s[0]);
      const std::string r2 = length(tab, prefix, "r2", s[1]);
      const std::string h = length(tab, prefix, "h", check_size(s[2], "height", what));
      code += "cylinder(h = " + h + ", r1 = " + drawn_radius(p, r1) + ", r2 = " +
              drawn_radius(p, r2) + ", center = true" + polygon_sides(tab, prefix, p) + ");";
      break;
    }
    case PrimitiveKind3D::Ellipsoid: {
      const std::string a = length(tab, prefix, "rx", check_size(s[0], "x semi-axis", what));
      const std::string b = length(tab, prefix, "ry", check_size(s[1], "y semi-axis", what));
      const std::string c = length(tab, prefix, "rz", check_size(s[2], "z semi-axis", what));
      code += "scale([" + a + ", " + b + ", " + c + "]) sphere(r = fn_sr(1));";
      spheres_ = true;
      break;
    }
    case PrimitiveKind3D::Torus: {
      check_size(s[0], "major radius", what);
      check_size(s[1], "minor radius", what);
      if (s[1] > s[0])
        throw InputError("cannot write .scad: " + what + " has a minor radius above its major radius");
      const std::string big = length(tab, prefix, "major_r", s[0]);
      const std::string small = length(tab, prefix, "minor_r", s[1]);
      code += "csg_torus(" + big + ", " + small + ");";
      circles_ = tori_ = true;
      break;
    }
    case PrimitiveKind3D::TriangularPrism: {
      const std::string w = length(tab, prefix, "w", check_size(s[0], "width", what));
      const std::string h = length(tab, prefix, "h", check_size(s[1], "height", what));
      const std::string dp = length(tab, prefix, "depth", check_size(s[2], "depth", what));
      // The apex offset is relative to the half width: more decimals than a length.
      const std::string ap = add(tab, prefix, "apex", check(p.apex, "apex", what), "[-4:0.01:4]", 6);
      code += "linear_extrude(height = " + dp + ", center = true) polygon([[-" + w + " / 2, -" +
              h + " / 2], [" + w + " / 2, -" + h + " / 2], [" + ap + " * " + w + " / 2, " + h +
              " / 2]]);";
      break;
    }
    case PrimitiveKind3D::Nurbs: code += nurbs(p, prefix, what); break;
    case PrimitiveKind3D::RoundedBox: code += rounded_box(tab, p, prefix, what); break;
  }
  if (!tab.vars.empty()) tabs_.push_back(std::move(tab));
  return code;
}

// As designers draw it: the rectangle of the corner centres grown by offset(r). The corner is
// drawn with the radius fn_corner gives it, so that its polygon keeps the fitted area and the
// flats stay on the fitted faces (the square shrinks as the radius grows).
std::string Writer::rounded_box(Tab& tab, const Primitive3D& p, const std::string& prefix,
                                const std::string& what) {
  const Vec3& s = p.dims;
  const std::string a = length(tab, prefix, "size_x", check_size(s[0], "size x", what));
  const std::string b = length(tab, prefix, "size_y", check_size(s[1], "size y", what));
  const std::string c = length(tab, prefix, "size_z", check_size(s[2], "size z", what));
  check_size(p.corner, "corner", what);
  if (p.corner > std::min(s[0], s[1]) / 2 * (1 + 1e-12))
    throw InputError("cannot write .scad: " + what + " has a corner over half its smaller side");
  const std::string r = "fn_corner(" + length(tab, prefix, "corner", p.corner) + ")";
  corners_ = true;
  return "linear_extrude(height = " + c + ", center = true) offset(r = " + r +
         ", $fn = corner_fn) square([" + a + " - 2 * " + r + ", " + b + " - 2 * " + r +
         "], center = true);";
}

// The patch's polyhedron within 1e-4 of its size (about 0.005 mm on a 60 mm die), as a module
// so that the body stays readable; its control net is not a Customizer parameter (edit the
// JSON or the FreeCAD feature's control points instead).
std::string Writer::nurbs(const Primitive3D& p, const std::string& prefix, const std::string& what) {
  if (!p.patch) throw InputError("cannot write .scad: " + what + " has no patch");
  for (const Vec3& v : p.patch->net())
    for (double c : v) check(c, "control point", what);
  const double tolerance = 1e-4 * std::max({p.dims[0], p.dims[1], p.dims[2]});
  const scad::PatchPolyhedron poly = scad::patch_polyhedron(*p.patch, tolerance, decimals_ + 2);
  char note[200];
  std::snprintf(note, sizeof note,
                "%s: polyhedron of %dx%d cells, deviation <= %.3g mm from the exact B-spline patch",
                prefix.c_str(), poly.cells_x, poly.cells_y, poly.deviation);
  notes_.push_back(note);
  modules_ += "// " + std::string(note) + "\nmodule csg_" + prefix + "()\n  " + poly.code + "\n\n";
  return "csg_" + prefix + "();";
}

}  // namespace

namespace {

// offset(r) rounds each of a square's corners with round($fn / 4) segments, vertices on the
// circle, the first and last on the square's edge normals (Clipper's round joins): with $fn a
// multiple of 4 each corner is a quarter of the circle's $fn-gon (else the count rounds a
// half either way). The quarter's area is then (corner_fn / 8) sin(360 / corner_fn) r^2, and
// the section's sx sy - (4 - corner_fn / 2 sin(360 / corner_fn)) r^2; fn_corner gives the
// radius that makes it the fitted sx sy - (4 - pi) corner^2. Whatever the file's circle fit:
// at the fitted radius a stadium's square would have no width, and OpenSCAD draws nothing.
void write_corner_radius(std::ostream& out) {
  out << "// Rounded boxes: offset(r) draws each corner as a quarter of a corner_fn-gon with its\n"
         "// vertices on the circle; fn_corner gives the radius whose corners keep the fitted "
         "area.\n";
  out << "corner_fn = 4 * ceil(segments / 4);\n";
  out << "function fn_corner(r) = r * sqrt((4 - PI) / (4 - corner_fn / 2 * sin(360 / corner_fn)));\n";
}

double model_extent(const Node3D& tree) {
  double extent = 0;
  for (const Primitive3D* p : leaves(tree)) {
    const double size = std::max({p->dims[0], p->dims[1], p->dims[2]});
    for (double c : {p->cx, p->cy, p->cz})
      if (std::isfinite(c) && std::isfinite(size)) extent = std::max(extent, std::fabs(c) + 2 * size);
  }
  return extent;
}

// The file for `tree`, or for the morph from `tree` to `*morph_b` (same structure).
std::string scad_text(const Node3D& tree, const ScadOptions3D& options, const Node3D* morph_b,
                      const std::string& source_b) {
  if (options.fn < 3 || options.fn > 10000)
    throw InputError("cannot write .scad: $fn must be between 3 and 10000");
  if (tree.primitive_count() == 0 || is_empty(tree))
    throw InputError("cannot write .scad: the tree has no primitives");

  // Sliders cover the model; values keep enough decimals that rounding moves a surface by
  // about 1e-5 of the model's size (and at least 4 decimals).
  const double extent = std::max(model_extent(tree), morph_b ? model_extent(*morph_b) : 0.0);
  const int decimals =
      extent > 0 ? std::clamp(static_cast<int>(std::ceil(5.0 - std::log10(extent))), 4, 12) : 4;

  // A morph's B end is written with A's rotations and the turn from them to B's.
  std::vector<Turn> turns;
  Node3D b_turned;
  if (morph_b) {
    b_turned = *morph_b;
    const std::vector<const Primitive3D*> la = leaves(tree);
    const std::vector<Primitive3D*> lb = leaves(b_turned);
    if (la.size() != lb.size())
      throw InputError("cannot write .scad: the two trees of the morph differ in structure");
    for (std::size_t i = 0; i < la.size(); ++i) {
      Turn t;
      relative_turn(la[i]->rotation, lb[i]->rotation, t.axis, t.degrees);
      turns.push_back(t);
      lb[i]->rotation = la[i]->rotation;
    }
  }
  Writer writer = morph_b ? Writer(decimals, extent, &turns, false) : Writer(decimals, extent);
  if (!morph_b) writer.share(tree);  // as in 2D: a morph's ends share nothing
  const std::string body = writer.geometry(tree, 1);
  std::vector<Tab> tabs_b;
  if (morph_b) {
    Writer other(decimals, extent, &turns, true);
    if (other.geometry(b_turned, 1) != body)
      throw InputError("cannot write .scad: the two trees of the morph differ in structure");
    tabs_b = other.tabs();
  }
  const std::string module = identifier(options.source, "model");

  std::ostringstream out;
  out << "// Generated by csgfit";
  if (!options.source.empty()) out << " from " << comment_safe(options.source);
  if (morph_b) out << " (morph = 0) and " << comment_safe(source_b) << " (morph = 1)";
  out << "\n// Units: those of the source model (mm), z up.\n";
  if (!options.summary.empty()) out << "// Fit: " << comment_safe(options.summary) << "\n";
  for (const std::string& note : writer.notes()) out << "// " << note << "\n";
  out << "// Every dimension below is a Customizer parameter (Window > Customizer).\n\n";
  if (morph_b) write_morph_slider(out, options.source, source_b);
  write_resolution(out, options.fn);
  if (morph_b)
    write_morph_tabs(out, writer.tabs(), tabs_b);
  else {
    const Tab shared = writer.shared_tab(1.0);
    if (!shared.vars.empty()) write_tabs(out, {shared});
    write_tabs(out, writer.tabs());
  }
  out << "/* [Hidden] */\n";
  out << "$fn = segments;\n";
  if (writer.uses_corners()) write_corner_radius(out);
  out << "\n";
  if (morph_b) write_morph_values(out, writer.tabs(), tabs_b);
  if (writer.uses_circles()) write_circle_radius(out, options.circle_fit);
  if (writer.uses_spheres()) {
    switch (options.circle_fit) {
      case CircleFit::Inscribed:
        out << "// Spheres are OpenSCAD's ring polyhedra with their vertices on the fitted "
               "sphere.\n";
        out << "function fn_sr(r) = r;\n\n";
        break;
      case CircleFit::Circumscribed:
        out << "// Spheres enlarged like circles, so the ring polygons' edges touch the sphere.\n";
        out << "function fn_sr(r) = r / cos(180 / $fn);\n\n";
        break;
      case CircleFit::EqualArea:
        out << "// OpenSCAD builds a sphere from floor(($fn + 1) / 2) rings of $fn-gons with "
               "their\n// vertices on the sphere: a stack of frusta. fn_sphere_volume is that "
               "polyhedron's\n// volume per (n / 2) sin(360 / n) at r = 1; fn_sr gives it the "
               "fitted sphere's volume.\n";
        out << "function fn_sphere_volume(rings, i = 0) = i >= rings - 1 ? 0 :\n"
               "  let(a = sin(180 * (i + 0.5) / rings), b = sin(180 * (i + 1.5) / rings),\n"
               "      h = cos(180 * (i + 0.5) / rings) - cos(180 * (i + 1.5) / rings))\n"
               "  h / 3 * (a * a + a * b + b * b) + fn_sphere_volume(rings, i + 1);\n";
        out << "function fn_sr(r) = r * pow(4 / 3 * PI / ($fn / 2 * sin(360 / $fn) *\n"
               "  fn_sphere_volume(floor(($fn + 1) / 2))), 1 / 3);\n\n";
        break;
    }
  }
  if (writer.uses_tori()) {
    out << "// A torus about the z axis: the circle of radius r at distance R, revolved. With\n"
           "// equal-area fn_r, stretching the profile by fn_r(1) across the axis gives the\n"
           "// revolved $fn-gon the torus's volume; min() keeps it off the axis when r = R.\n";
    out << "module csg_torus(R, r)\n"
           "  rotate_extrude() translate([fn_r(R), 0]) scale([min(fn_r(1), R / r), 1]) "
           "circle(r = fn_r(r));\n\n";
  }
  out << writer.modules();
  out << "module " << module << "() {\n" << body << "}\n\n";
  out << module << "();\n";
  return out.str();
}

}  // namespace

std::string to_scad(const Node3D& tree, const ScadOptions3D& options) {
  return scad_text(tree, options, nullptr, {});
}

std::string to_scad_morph(const Node3D& a, const Node3D& b, const std::string& source_b,
                          const ScadOptions3D& options) {
  return scad_text(a, options, &b, source_b);
}

}  // namespace csgfit
