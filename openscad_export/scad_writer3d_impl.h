// Internal to openscad_export/: the 3D .scad writer's class, shared by scad_writer3d.cpp (the
// primitives and the file) and scad_sweep_writer.cpp (subtrees written as linear_extrude or
// rotate_extrude of their profile).
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/model/sweeps.h"
#include "scad_format.h"
#include "scad_tree_writer.h"

namespace csgfit::scad {

inline constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

/// A morph's turn of one primitive: R(axis, t * degrees) after its rotation at A.
struct Turn {
  Vec3 axis{0, 0, 1};
  double degrees = 0;
};

class Writer3D : public TreeWriter<Writer3D, Node3D> {
 public:
  Writer3D(int decimals, double extent) : decimals_(decimals), extent_(extent) {}
  /// One end of a morph: sizes may be 0, and each primitive turns by `turns` (pre-order) on top
  /// of its rotation (which the caller makes A's at both ends); `at_b` says which end.
  Writer3D(int decimals, double extent, const std::vector<Turn>* turns, bool at_b)
      : decimals_(decimals), extent_(extent), turns_(turns), at_b_(at_b) {}

  /// Writes these subtrees (find_sweeps of the tree about to be written, which must outlive
  /// the writer) as linear_extrude or rotate_extrude of their profile.
  void use_sweeps(const std::vector<Sweep>* sweeps);

  std::string primitive(const Primitive3D& p);

  bool uses_spheres() const { return spheres_; }
  bool uses_circles() const { return circles_; }
  bool uses_tori() const { return tori_; }
  bool uses_revolutions() const { return revolutions_; }
  bool uses_half_discs() const { return half_discs_; }
  bool uses_corners() const { return corners_; }
  /// Modules the body calls (one polyhedron per NURBS terminal) and the header lines saying
  /// how far each strays from its exact patch.
  const std::string& modules() const { return modules_; }
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  friend class TreeWriter<Writer3D, Node3D>;

  // A primitive's names in the file: "box_3" for its parameters, "Box 3" for its tab, and
  // "primitive 3 (box)" for errors. Numbers it (the next count_).
  struct Names {
    std::string prefix, title, what;
  };
  Names names_of(const Primitive3D& p);

  // The TreeWriter hooks: a sweep is written whole, as the extrusion of its profile.
  bool writes_whole(const Node3D& n) const { return !sweep_ && sweep_at(n); }
  std::string whole(const Node3D& n, int indent);
  const Sweep* sweep_at(const Node3D& n) const {
    const auto it = sweep_of_.find(&n);
    return it == sweep_of_.end() ? nullptr : it->second;
  }
  // A leaf of the sweep being written, as its section in the sweep's plane.
  std::string section(const Primitive3D& p);
  std::string linear_section(const Primitive3D& p, const SweepSection& s, Tab& tab,
                             const Names& n);
  std::string revolved_section(const Primitive3D& p, const SweepSection& s, Tab& tab,
                               const Names& n);

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
  std::string position(Tab& tab, const std::string& prefix, const char* field, double v) {
    return add(tab, prefix, field, v, position_range(v), decimals_);
  }
  // An angle in degrees; more decimals than a length: a degree turns a 100 mm part's end by
  // 1.7 mm.
  static std::string angle(Tab& tab, const std::string& prefix, const char* field, double v) {
    return add(tab, prefix, field, v, "[-180:0.1:180]", 6);
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

  // "rotate([a, b, c]) " with a variable per non-zero angle, or "" for no rotation. When only
  // the turn's local z axis matters (a round solid's), rotate([a, b, 0]).
  std::string rotation(Tab& tab, const std::string& prefix, const Quaternion& q, bool axis_only,
                       const std::string& what) {
    Vec3 e;
    if (axis_only) {
      // rotate([a, b, 0]) takes local z to the axis (x, y, z) when a = -asin(y), b = atan2(x, z).
      const Mat3 m = q.matrix();
      const double ax = m[0][2], ay = m[1][2], az = m[2][2];
      e = {-std::asin(std::clamp(ay, -1.0, 1.0)) * kRadToDeg, std::atan2(ax, az) * kRadToDeg, 0};
    } else {
      e = q.euler_deg();
    }
    static const char* const names[3] = {"rot_x", "rot_y", "rot_z"};
    std::string parts[3];
    bool any = false;
    for (int i = 0; i < 3; ++i) {
      check(e[i], "rotation", what);
      if (number(e[i], 6) == "0") {
        parts[i] = "0";
        continue;
      }
      any = true;
      parts[i] = angle(tab, prefix, names[i], e[i]);
    }
    if (!any) return "";
    return "rotate([" + parts[0] + ", " + parts[1] + ", " + parts[2] + "]) ";
  }

  int decimals_;
  double extent_;
  const std::vector<Turn>* turns_ = nullptr;
  bool at_b_ = false;
  bool spheres_ = false, circles_ = false, tori_ = false, revolutions_ = false,
       half_discs_ = false, corners_ = false;
  std::string modules_;
  std::vector<std::string> notes_;
  std::map<const Node3D*, const Sweep*> sweep_of_;
  const Sweep* sweep_ = nullptr;  // the sweep whose profile is being written
  int extrusions_ = 0, revolved_ = 0;

  std::string nurbs(const Primitive3D& p, const std::string& prefix, const std::string& what);
  // A rounded box's section, "offset(r = ...) square([w, h], center = true)" less the corners:
  // w and h its sides as written (its x and y, or the sides its sweep's plane sees).
  std::string rounded_square(Tab& tab, const Primitive3D& p, const std::string& prefix,
                             const std::string& what, const std::string& w, const std::string& h);
};

}  // namespace csgfit::scad
