// The 3D writer's sweeps (csgfit/model/sweeps.h): a subtree that is a profile swept along an
// axis is written as linear_extrude of the 2D tree of its leaves' sections, one swept about an
// axis as rotate_extrude of its half profile, each leaf keeping its own Customizer tab.
#include <string>
#include <vector>

#include "scad_writer3d_impl.h"

namespace csgfit::scad {

void Writer3D::use_sweeps(const std::vector<Sweep>* sweeps) {
  sweep_of_.clear();
  if (sweeps)
    for (const Sweep& s : *sweeps) sweep_of_[s.root] = &s;
}

// "translate([...]) rotate([...]) linear_extrude(height = h)" or "... rotate_extrude()", with
// the sweep's own tab (before its leaves' tabs), then the profile, one level deeper.
std::string Writer3D::whole(const Node3D& n, int indent) {
  const Sweep& s = *sweep_at(n);
  const bool linear = s.kind == SweepKind::Linear;
  const std::string num = std::to_string(linear ? ++extrusions_ : ++revolved_);
  const std::string prefix = (linear ? "extrude_" : "revolve_") + num;
  const std::string what = (linear ? "extrusion " : "revolution ") + num;
  Tab tab{(linear ? "Extrusion " : "Revolution ") + num, {}};
  static const char* const axes[3] = {"x", "y", "z"};
  bool moved = false;
  for (double v : s.origin) moved = moved || number(check(v, "position", what), decimals_) != "0";
  std::string head;
  if (moved) {
    std::string at[3];
    for (int i = 0; i < 3; ++i)
      at[i] = number(s.origin[i], decimals_) == "0" ? "0" : position(tab, prefix, axes[i], s.origin[i]);
    head = "translate([" + at[0] + ", " + at[1] + ", " + at[2] + "]) ";
  }
  // A revolution's turn about its own axis is no shape: two angles say where the axis goes.
  head += rotation(tab, prefix, s.rotation, !linear, what);
  if (linear) {
    head += "linear_extrude(height = " + length(tab, prefix, "h", check_size(s.height, "height", what)) + ")";
  } else {
    // OpenSCAD revolves the profile into $fn-gons: stretched across the axis by fn_r(1), each
    // of them has the area of the circle it stands for, as a cylinder's fn_r radius gives it.
    head += "rotate_extrude() scale([fn_r(1), 1])";
    circles_ = revolutions_ = true;
  }
  tabs_.push_back(std::move(tab));
  sweep_ = &s;
  const std::string profile = geometry(n, indent + 1);
  sweep_ = nullptr;
  return std::string(static_cast<std::size_t>(indent) * 2, ' ') + head + "\n" + profile;
}

std::string Writer3D::section(const Primitive3D& p) {
  const SweepSection* s = sweep_->section_of(&p);
  const Names names = names_of(p);
  if (!s) throw InputError("cannot write .scad: " + names.what + " is not in its sweep");
  Tab tab{names.title, {}};
  const std::string code = sweep_->kind == SweepKind::Linear
                               ? linear_section(p, *s, tab, names)
                               : revolved_section(p, *s, tab, names);
  if (!tab.vars.empty()) tabs_.push_back(std::move(tab));
  return code;
}

// The leaf's cross-section in the extrusion's plane; its length along the axis is the
// extrusion's height.
std::string Writer3D::linear_section(const Primitive3D& p, const SweepSection& s, Tab& tab,
                                     const Names& n) {
  const std::string& prefix = n.prefix;
  const std::string x = position(tab, prefix, "cx", check(s.x, "centre x", n.what));
  const std::string y = position(tab, prefix, "cy", check(s.y, "centre y", n.what));
  const std::string at = "translate([" + x + ", " + y + "]) ";
  const std::string turn =
      number(check(s.angle, "angle", n.what), 6) == "0" ? "" : "rotate(" + angle(tab, prefix, "angle", s.angle) + ") ";
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::RoundedBox: {
      static const char* const sides[3] = {"size_x", "size_y", "size_z"};
      const int i = s.across[0], j = s.across[1];
      const std::string w = length(tab, prefix, sides[i], check_size(d[i], sides[i], n.what));
      const std::string h = length(tab, prefix, sides[j], check_size(d[j], sides[j], n.what));
      if (p.kind == PrimitiveKind3D::RoundedBox)
        return at + turn + rounded_square(tab, p, prefix, n.what, w, h) + ";";
      return at + turn + "square([" + w + ", " + h + "], center = true);";
    }
    case PrimitiveKind3D::Cylinder: {
      const std::string r =
          length(tab, p, DimensionField::Radius, prefix, "r", check_size(d[0], "radius", n.what));
      if (!p.is_polygonal()) return at + "circle(r = " + drawn_radius(p, r) + ");";
      return at + turn + "circle(r = " + r + polygon_sides(tab, prefix, p) + ");";
    }
    case PrimitiveKind3D::TriangularPrism: {
      const std::string w = length(tab, prefix, "w", check_size(d[0], "width", n.what));
      const std::string h = length(tab, prefix, "h", check_size(d[1], "height", n.what));
      const std::string ap = add(tab, prefix, "apex", check(p.apex, "apex", n.what), "[-4:0.01:4]", 6);
      // Seen from the other end of its axis, the triangle is its mirror image.
      const std::string mirror = s.flipped ? "mirror([0, 1]) " : "";
      return at + turn + mirror + "polygon([[-" + w + " / 2, -" + h + " / 2], [" + w + " / 2, -" +
             h + " / 2], [" + ap + " * " + w + " / 2, " + h + " / 2]]);";
    }
    default: throw InputError("cannot write .scad: " + n.what + " has no section to extrude");
  }
}

// The leaf's half profile: x the distance from the axis, y the height along it.
std::string Writer3D::revolved_section(const Primitive3D& p, const SweepSection& s, Tab& tab,
                                       const Names& n) {
  const std::string& prefix = n.prefix;
  const std::string z = position(tab, prefix, "cz", check(s.y, "centre along the axis", n.what));
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Cylinder: {
      const std::string r =
          length(tab, p, DimensionField::Radius, prefix, "r", check_size(d[0], "radius", n.what));
      const std::string h =
          length(tab, p, DimensionField::Length, prefix, "h", check_size(d[2], "height", n.what));
      return "translate([0, " + z + " - " + h + " / 2]) square([" + r + ", " + h + "]);";
    }
    case PrimitiveKind3D::Cone: {
      check(d[0], "bottom radius", n.what);
      check(d[1], "top radius", n.what);
      if (d[0] < 0 || d[1] < 0 || !(std::max(d[0], d[1]) > 0))
        throw InputError("cannot write .scad: " + n.what + " has a negative or zero radius");
      const std::string r1 = length(tab, prefix, "r1", d[0]);
      const std::string r2 = length(tab, prefix, "r2", d[1]);
      const std::string h = length(tab, prefix, "h", check_size(d[2], "height", n.what));
      const std::string& low = s.flipped ? r2 : r1;
      const std::string& high = s.flipped ? r1 : r2;
      return "translate([0, " + z + "]) polygon([[0, -" + h + " / 2], [" + low + ", -" + h +
             " / 2], [" + high + ", " + h + " / 2], [0, " + h + " / 2]]);";
    }
    case PrimitiveKind3D::Torus: {
      check_size(d[0], "major radius", n.what);
      check_size(d[1], "minor radius", n.what);
      if (d[1] > d[0])
        throw InputError("cannot write .scad: " + n.what + " has a minor radius above its major radius");
      const std::string big = length(tab, prefix, "major_r", d[0]);
      const std::string small = length(tab, prefix, "minor_r", d[1]);
      // The tube's $fn-gon reaches fn_r(r) from its centre: one near the axis is narrowed so
      // that it stays off it (rotate_extrude refuses a profile across its axis).
      const std::string narrowed =
          d[0] < 2 * d[1] ? "scale([min(1, " + big + " / fn_r(" + small + ")), 1]) " : "";
      circles_ = true;
      return "translate([" + big + ", " + z + "]) " + narrowed + "circle(r = fn_r(" + small + "));";
    }
    case PrimitiveKind3D::Sphere: {
      const std::string r =
          length(tab, p, DimensionField::Radius, prefix, "r", check_size(d[0], "radius", n.what));
      circles_ = half_discs_ = true;
      return "translate([0, " + z + "]) csg_half_disc(fn_r(" + r + "));";
    }
    default: throw InputError("cannot write .scad: " + n.what + " has no profile to revolve");
  }
}

}  // namespace csgfit::scad
