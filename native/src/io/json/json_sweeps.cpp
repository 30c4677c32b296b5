#include "io/json/json_sweeps.h"

#include <string>

#include "csgfit/model/sweeps.h"

namespace csgfit::json_detail {

namespace {

constexpr const char* kWhere = "sweeps";

double finite(double v) {
  if (!std::isfinite(v)) fail(kWhere, "a value is not a finite number");
  return v;
}

ojson point(double x, double y) { return ojson::array({finite(x), finite(y)}); }

// A linear sweep's section: the leaf's cross-section in the plane.
ojson linear_section(const SweepSection& s) {
  const Primitive3D& p = *s.leaf;
  const Vec3& d = p.dims;
  ojson j{{"leaf", s.leaf_index}};
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::RoundedBox: {
      // A rounded box's section is the box's rectangle with its corners rounded.
      const bool rounded = p.kind == PrimitiveKind3D::RoundedBox;
      j["type"] = rounded ? "rounded_rectangle" : "rectangle";
      j["cx"] = finite(s.x), j["cy"] = finite(s.y);
      j["w"] = d[s.across[0]], j["h"] = d[s.across[1]], j["angle"] = finite(s.angle);
      if (rounded) j["r"] = p.corner;
      break;
    }
    case PrimitiveKind3D::Cylinder:
      j["type"] = "circle";
      j["cx"] = finite(s.x), j["cy"] = finite(s.y), j["r"] = d[0];
      if (p.is_polygonal()) j["sides"] = p.sides, j["angle"] = finite(s.angle);
      break;
    default:  // the triangular prism; seen from behind (flipped), its mirror image is the
              // triangle turned half round with the apex on the other side
      j["type"] = "triangle";
      j["cx"] = finite(s.x), j["cy"] = finite(s.y), j["w"] = d[0], j["h"] = d[1];
      j["angle"] = finite(s.flipped ? s.angle + 180 : s.angle);
      j["apex"] = finite(s.flipped ? -p.apex : p.apex);
      break;
  }
  return j;
}

// A revolution's section: the leaf's half profile, x from the axis, y along it.
ojson revolved_section(const SweepSection& s) {
  const Primitive3D& p = *s.leaf;
  const Vec3& d = p.dims;
  const double y = finite(s.y);
  ojson j{{"leaf", s.leaf_index}};
  switch (p.kind) {
    case PrimitiveKind3D::Cylinder:
      j["type"] = "rectangle";
      j["cx"] = d[0] / 2, j["cy"] = y, j["w"] = d[0], j["h"] = d[2], j["angle"] = 0;
      break;
    case PrimitiveKind3D::Cone: {
      const double low = s.flipped ? d[1] : d[0], high = s.flipped ? d[0] : d[1];
      ojson points = ojson::array({point(0, y - d[2] / 2)});
      // A pointed end is one corner, not two.
      if (low > 0) points.push_back(point(low, y - d[2] / 2));
      if (high > 0) points.push_back(point(high, y + d[2] / 2));
      points.push_back(point(0, y + d[2] / 2));
      j["type"] = "polygon";
      j["points"] = std::move(points);
      break;
    }
    case PrimitiveKind3D::Torus:
      j["type"] = "circle";
      j["cx"] = d[0], j["cy"] = y, j["r"] = d[1];
      break;
    default:  // the sphere
      j["type"] = "half_disc";
      j["cx"] = 0, j["cy"] = y, j["r"] = d[0];
      break;
  }
  return j;
}

}  // namespace

ojson sweeps_to_json(const Node3D& tree) {
  ojson out = ojson::array();
  for (const Sweep& s : find_sweeps(tree)) {
    const bool linear = s.kind == SweepKind::Linear;
    const Quaternion& q = s.rotation;
    ojson j{{"node", s.node},
            {"kind", linear ? "linear_extrude" : "rotate_extrude"},
            {"center", {finite(s.origin[0]), finite(s.origin[1]), finite(s.origin[2])}},
            {"rotation", {finite(q.w), finite(q.x), finite(q.y), finite(q.z)}}};
    if (linear) j["height"] = finite(s.height);
    ojson sections = ojson::array();
    for (const SweepSection& section : s.sections)
      sections.push_back(linear ? linear_section(section) : revolved_section(section));
    j["sections"] = std::move(sections);
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace csgfit::json_detail
