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
#include "csgfit/model/shared_dimensions.h"
#include "csgfit/model/sweeps.h"
#include "scad_format.h"
#include "scad_patch.h"
#include "scad_tree_writer.h"
#include "scad_writer3d_impl.h"

namespace csgfit::scad {

Writer3D::Names Writer3D::names_of(const Primitive3D& p) {
  ++count_;
  numbered(p);
  const std::string num = std::to_string(count_);
  Names n;
  switch (p.kind) {
    case PrimitiveKind3D::Box: n.prefix = "box_", n.title = "Box "; break;
    case PrimitiveKind3D::Sphere: n.prefix = "sphere_", n.title = "Sphere "; break;
    case PrimitiveKind3D::Cylinder: n.prefix = "cyl_", n.title = "Cylinder "; break;
    case PrimitiveKind3D::Cone: n.prefix = "cone_", n.title = "Cone "; break;
    case PrimitiveKind3D::Ellipsoid: n.prefix = "ellipsoid_", n.title = "Ellipsoid "; break;
    case PrimitiveKind3D::Torus: n.prefix = "torus_", n.title = "Torus "; break;
    case PrimitiveKind3D::TriangularPrism: n.prefix = "prism_", n.title = "Prism "; break;
    case PrimitiveKind3D::Nurbs: n.prefix = "nurbs_", n.title = "NURBS patch "; break;
    case PrimitiveKind3D::RoundedBox: n.prefix = "rbox_", n.title = "Rounded box "; break;
  }
  n.prefix += num;
  n.title += num;
  n.what = "primitive " + num + " (" + std::string(to_string(p.kind)) + ")";
  return n;
}

std::string Writer3D::primitive(const Primitive3D& p) {
  if (sweep_) return section(p);
  const Names names = names_of(p);
  const std::string& prefix = names.prefix;
  const std::string& title = names.title;
  const std::string& what = names.what;
  Tab tab{title, {}};
  const int d = decimals_;
  const std::string vx = add(tab, prefix, "cx", check(p.cx, "centre x", what), position_range(p.cx), d);
  const std::string vy = add(tab, prefix, "cy", check(p.cy, "centre y", what), position_range(p.cy), d);
  const std::string vz = add(tab, prefix, "cz", check(p.cz, "centre z", what), position_range(p.cz), d);
  const Vec3& s = p.dims;
  std::string code = "translate([" + vx + ", " + vy + ", " + vz + "]) ";
  if (p.kind != PrimitiveKind3D::Sphere) code += turn(tab, prefix) + rotation(tab, prefix, p.rotation, is_axially_symmetric(p), what);
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
    case PrimitiveKind3D::RoundedBox: {
      const std::string a = length(tab, prefix, "size_x", check_size(s[0], "size x", what));
      const std::string b = length(tab, prefix, "size_y", check_size(s[1], "size y", what));
      const std::string c = length(tab, prefix, "size_z", check_size(s[2], "size z", what));
      code += "linear_extrude(height = " + c + ", center = true) " +
              rounded_square(tab, p, prefix, what, a, b) + ";";
      break;
    }
  }
  if (!tab.vars.empty()) tabs_.push_back(std::move(tab));
  return code;
}

// As designers draw it: the rectangle of the corner centres grown by offset(r). The corner is
// drawn with the radius fn_corner gives it, so that its polygon keeps the fitted area and the
// flats stay on the fitted faces (the square shrinks as the radius grows).
std::string Writer3D::rounded_square(Tab& tab, const Primitive3D& p, const std::string& prefix,
                                     const std::string& what, const std::string& w,
                                     const std::string& h) {
  check_size(p.corner, "corner", what);
  if (p.corner > std::min(p.dims[0], p.dims[1]) / 2 * (1 + 1e-12))
    throw InputError("cannot write .scad: " + what + " has a corner over half its smaller side");
  const std::string r = "fn_corner(" + length(tab, prefix, "corner", p.corner) + ")";
  corners_ = true;
  return "offset(r = " + r + ", $fn = corner_fn) square([" + w + " - 2 * " + r + ", " + h +
         " - 2 * " + r + "], center = true)";
}

// The patch's polyhedron within 1e-4 of its size (about 0.005 mm on a 60 mm die), as a module
// so that the body stays readable; its control net is not a Customizer parameter (edit the
// JSON or the FreeCAD feature's control points instead).
std::string Writer3D::nurbs(const Primitive3D& p, const std::string& prefix, const std::string& what) {
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

}  // namespace csgfit::scad

namespace csgfit {

namespace {

// The writers' shared helpers (scad_format.h, scad_tree_writer.h, scad_writer3d_impl.h).
using namespace scad;

// csg_torus narrows its profile across the axis to this share of R / r at most: a horn torus
// (r = R, where the search clamps r) whose profile touched the axis would revolve into a mesh
// that is not closed, which OpenSCAD drops from a difference. 0.1% of its volume is the price.
constexpr double kTorusAxisClearance = 0.999;

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

// fn_sr: the radius that gives OpenSCAD's sphere polyhedron what the circle fit asks of it.
void write_sphere_radius(std::ostream& out, CircleFit fit) {
  switch (fit) {
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
  Writer3D writer = morph_b ? Writer3D(decimals, extent, &turns, false) : Writer3D(decimals, extent);
  // As in 2D, a morph's ends share nothing; nor are they swept (each end may sweep apart).
  const std::vector<Sweep> sweeps = morph_b ? std::vector<Sweep>() : find_sweeps(tree);
  if (!morph_b) {
    writer.use_sweeps(&sweeps);
    // A cylinder's length is the extrusion's height in a linear sweep: not a dimension there.
    std::vector<bool> extruded(tree.primitive_count(), false);
    for (const Sweep& s : sweeps)
      for (const SweepSection& section : s.sections)
        extruded[section.leaf_index] = s.kind == SweepKind::Linear;
    writer.share(tree, shared_dimensions(tree, [&](const DimensionUse& u) {
                   return u.field != DimensionField::Length || !extruded[u.leaf];
                 }));
  }
  const std::string body = writer.geometry(tree, 1);
  std::vector<Tab> tabs_b;
  if (morph_b) {
    Writer3D other(decimals, extent, &turns, true);
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
  if (writer.uses_revolutions())
    out << "// rotate_extrude() sweeps $fn-gons: a profile stretched across its axis by fn_r(1)\n"
           "// gives each the area of the circle it stands for, as fn_r does a cylinder's.\n\n";
  if (writer.uses_half_discs())
    out << "// The half x >= 0 of a circle: a sphere's profile (rotate_extrude refuses one that\n"
           "// crosses its axis).\n"
           "module csg_half_disc(r) intersection() { circle(r = r); translate([0, -r]) "
           "square([r, 2 * r]); }\n\n";
  if (writer.uses_spheres()) write_sphere_radius(out, options.circle_fit);
  if (writer.uses_tori()) {
    out << "// A torus about the z axis: the circle of radius r at distance R, revolved. With\n"
           "// equal-area fn_r, stretching the profile by fn_r(1) across the axis gives the\n"
           "// revolved $fn-gon the torus's volume; min() keeps it a hair off the axis when\n"
           "// r is about R (a profile touching the axis makes a mesh CGAL cannot subtract).\n";
    out << "module csg_torus(R, r)\n"
           "  rotate_extrude() translate([fn_r(R), 0]) scale([min(fn_r(1), "
        << kTorusAxisClearance << " * R / r), 1]) circle(r = fn_r(r));\n\n";
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
