#include "shapes.h"

#include <algorithm>
#include <cmath>

#include "csgfit/error.h"
#include "csgfit/optimise/sample_set.h"
#include "matrix4.h"

namespace csgfit::scad_shapes {
namespace {

using opt::Box;
using opt::Point;
using Type = ScadValue::Type;

constexpr double kPi = 3.14159265358979323846;

double number_arg(const ScadCall& c, const char* name, double fallback, const std::string& where) {
  const ScadValue* v = c.argument(name);
  if (!v || v->type == Type::Undef) return fallback;
  if (v->type != Type::Number) throw InputError(where + ": " + c.name + "'s " + name + " is not a number");
  return v->number;
}

bool bool_arg(const ScadCall& c, const char* name) {
  const ScadValue* v = c.argument(name);
  return v && v->type == Type::Bool && v->boolean;
}

// A number or a vector of `n` numbers (cube's size, linear_extrude's scale).
std::array<double, 3> sizes_arg(const ScadCall& c, const char* name, std::size_t n, double fallback,
                                const std::string& where) {
  std::array<double, 3> out{fallback, fallback, fallback};
  const ScadValue* v = c.argument(name);
  if (!v || v->type == Type::Undef) return out;
  if (v->type == Type::Number) return {v->number, v->number, v->number};
  if (v->type != Type::Vector || v->items.size() < n)
    throw InputError(where + ": " + c.name + "'s " + name + " is not " + std::to_string(n) + " numbers");
  for (std::size_t i = 0; i < n; ++i) {
    if (v->items[i].type != Type::Number) throw InputError(where + ": " + c.name + "'s " + name + " is not numbers");
    out[i] = v->items[i].number;
  }
  return out;
}

double radius_arg(const ScadCall& c, const char* r, const char* d, double fallback, const std::string& where) {
  const ScadValue* dv = c.argument(d);
  if (dv && dv->type == Type::Number) return dv->number / 2;
  return number_arg(c, r, fallback, where);
}

void require_positive(double v, const ScadCall& c, const char* what, const std::string& where) {
  if (!(v > 0) || !std::isfinite(v))
    throw InputError(where + ": " + c.name + " has a " + what + " of " + std::to_string(v) + " (must be > 0)");
}

// The world halfspace of a local shape: the test runs on the inverse image of the point, the
// bounds are those of the local box's corners.
opt::Halfspace<3> placed3(const Box<3>& local, const Matrix4& world, std::function<bool(double, double, double)> inside) {
  opt::Halfspace<3> h;
  const Matrix4 inv = scadm::inverse_affine(world);
  h.contains = [inv, inside = std::move(inside)](const Point<3>& p) {
    const auto q = scadm::apply(inv, p[0], p[1], p[2]);
    return inside(q[0], q[1], q[2]);
  };
  h.bounds.lo = {INFINITY, INFINITY, INFINITY};
  h.bounds.hi = {-INFINITY, -INFINITY, -INFINITY};
  for (int corner = 0; corner < 8; ++corner) {
    const auto w = scadm::apply(world, corner & 1 ? local.hi[0] : local.lo[0], corner & 2 ? local.hi[1] : local.lo[1],
                                corner & 4 ? local.hi[2] : local.lo[2]);
    for (int a = 0; a < 3; ++a) h.bounds.lo[a] = std::min(h.bounds.lo[a], w[a]), h.bounds.hi[a] = std::max(h.bounds.hi[a], w[a]);
  }
  return h;
}

opt::Halfspace<2> placed2(const Box<2>& local, const Matrix4& world, std::function<bool(double, double)> inside) {
  const Box<3> box{{local.lo[0], local.lo[1], 0}, {local.hi[0], local.hi[1], 0}};
  Matrix4 planar = world;  // the xy part; z is ignored in 2D
  planar[2] = planar[6] = planar[8] = planar[9] = planar[11] = 0;
  planar[10] = 1;
  const opt::Halfspace<3> h3 = placed3(box, planar, [inside = std::move(inside)](double x, double y, double) { return inside(x, y); });
  opt::Halfspace<2> h;
  h.bounds = {{h3.bounds.lo[0], h3.bounds.lo[1]}, {h3.bounds.hi[0], h3.bounds.hi[1]}};
  h.contains = [c = h3.contains](const Point<2>& p) { return c({p[0], p[1], 0}); };
  return h;
}

std::vector<std::array<double, 2>> polygon_points(const ScadCall& c, const std::string& where) {
  const ScadValue* v = c.argument("points");
  if (!v) v = c.arguments.empty() ? nullptr : &c.arguments[0].second;
  std::vector<std::array<double, 2>> pts;
  if (!v || v->type != Type::Vector) throw InputError(where + ": polygon has no points");
  for (const ScadValue& p : v->items) {
    if (p.type != Type::Vector || p.items.size() < 2 || p.items[0].type != Type::Number || p.items[1].type != Type::Number)
      throw InputError(where + ": a polygon point is not [x, y]");
    pts.push_back({p.items[0].number, p.items[1].number});
  }
  if (pts.size() < 3) throw InputError(where + ": polygon has fewer than 3 points");
  return pts;
}

// The paths as index lists (all points in order when there are none).
std::vector<std::vector<std::size_t>> polygon_paths(const ScadCall& c, std::size_t n, const std::string& where) {
  const ScadValue* v = c.argument("paths");
  if (!v || v->type != Type::Vector) {
    std::vector<std::size_t> all(n);
    for (std::size_t i = 0; i < n; ++i) all[i] = i;
    return {all};
  }
  std::vector<std::vector<std::size_t>> paths;
  for (const ScadValue& path : v->items) {
    std::vector<std::size_t> ids;
    for (const ScadValue& i : path.items) {
      if (i.type != Type::Number || i.number < 0 || i.number >= static_cast<double>(n))
        throw InputError(where + ": a polygon path names a point it does not have");
      ids.push_back(static_cast<std::size_t>(i.number));
    }
    paths.push_back(ids);
  }
  return paths;
}

// Even-odd: OpenSCAD's paths after the first are holes (and holes in holes are solid).
bool inside_polygon(const std::vector<std::array<double, 2>>& pts, const std::vector<std::vector<std::size_t>>& paths,
                    double x, double y) {
  bool in = false;
  for (const auto& path : paths) {
    for (std::size_t i = 0, j = path.size() - 1; i < path.size(); j = i++) {
      const auto& a = pts[path[i]];
      const auto& b = pts[path[j]];
      if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
    }
  }
  return in;
}

// OpenSCAD's number of fragments of a circle of radius r (Calc::get_fragments_from_r), so that
// a halfspace is the polygon or polyhedron OpenSCAD renders, not the smooth shape: a decision
// such as "this cube lies in that cylinder" must hold for what the user sees.
int fragments(const ScadCall& c, double r, const std::string& where) {
  const double fn = number_arg(c, "$fn", 0, where), fa = number_arg(c, "$fa", 12, where),
               fs = number_arg(c, "$fs", 2, where);
  if (r < 1e-10) return 3;
  if (fn > 0) return fn >= 3 ? static_cast<int>(std::min(fn, 1e6)) : 3;
  const double by_angle = fa > 0 ? 360.0 / fa : 1e6, by_size = fs > 0 ? r * 2 * kPi / fs : 1e6;
  return static_cast<int>(std::ceil(std::max(std::min(std::min(by_angle, by_size), 1e6), 5.0)));
}

// Inside OpenSCAD's regular n-gon of circumradius R (vertex i at 360 i / n degrees).
bool inside_ngon(double x, double y, double R, int n) {
  if (R <= 0) return false;
  const double step = 2 * kPi / n;
  double phi = std::atan2(y, x);
  if (phi < 0) phi += 2 * kPi;
  const double mid = (std::floor(phi / step) + 0.5) * step;
  return x * std::cos(mid) + y * std::sin(mid) <= R * std::cos(step / 2);
}

// OpenSCAD's sphere: (n + 1) / 2 rings of n-gons at polar angles 180 (i + 0.5) / rings, joined
// face to face, so that a section at height z is the n-gon of the two rings' radii blended.
bool inside_sphere_polyhedron(double x, double y, double z, double r, int n) {
  const int rings = (n + 1) / 2;
  auto ring_z = [&](int i) { return r * std::cos(kPi * (i + 0.5) / rings); };
  auto ring_r = [&](int i) { return r * std::sin(kPi * (i + 0.5) / rings); };
  if (z > ring_z(0) || z < ring_z(rings - 1)) return false;
  if (rings == 1) return inside_ngon(x, y, ring_r(0), n);
  int i = 0;
  while (i + 1 < rings - 1 && z < ring_z(i + 1)) ++i;
  const double t = (ring_z(i) - z) / (ring_z(i) - ring_z(i + 1));
  return inside_ngon(x, y, ring_r(i) + t * (ring_r(i + 1) - ring_r(i)), n);
}

}  // namespace

bool is_extrusion(const std::string& n) { return n == "linear_extrude" || n == "rotate_extrude"; }
bool is_2d_primitive(const std::string& n) { return n == "circle" || n == "square" || n == "polygon"; }
bool is_3d_primitive(const std::string& n) { return n == "cube" || n == "sphere" || n == "cylinder"; }

std::optional<opt::Halfspace<3>> primitive3(const ScadCall& c, const Matrix4& world, const std::string& where) {
  if (c.name == "cube") {
    const auto s = sizes_arg(c, "size", 3, 1, where);
    for (double v : s) require_positive(v, c, "size", where);
    const bool centred = bool_arg(c, "center");
    Box<3> b{{0, 0, 0}, {s[0], s[1], s[2]}};
    if (centred) b = {{-s[0] / 2, -s[1] / 2, -s[2] / 2}, {s[0] / 2, s[1] / 2, s[2] / 2}};
    return placed3(b, world, [b](double x, double y, double z) { return b.contains({x, y, z}); });
  }
  if (c.name == "sphere") {
    const double r = radius_arg(c, "r", "d", 1, where);
    require_positive(r, c, "radius", where);
    const int n = fragments(c, r, where);
    return placed3({{-r, -r, -r}, {r, r, r}}, world,
                   [r, n](double x, double y, double z) { return inside_sphere_polyhedron(x, y, z, r, n); });
  }
  if (c.name == "cylinder") {
    const double h = number_arg(c, "h", 1, where);
    const double r = radius_arg(c, "r", "d", 1, where);
    const double r1 = radius_arg(c, "r1", "d1", r, where), r2 = radius_arg(c, "r2", "d2", r, where);
    require_positive(h, c, "height", where);
    if (!(r1 >= 0 && r2 >= 0) || r1 + r2 <= 0) throw InputError(where + ": cylinder has no radius");
    const double z0 = bool_arg(c, "center") ? -h / 2 : 0, rmax = std::max(r1, r2);
    const int n = fragments(c, rmax, where);
    return placed3({{-rmax, -rmax, z0}, {rmax, rmax, z0 + h}}, world, [=](double x, double y, double z) {
      if (z < z0 || z > z0 + h) return false;
      return inside_ngon(x, y, r1 + (r2 - r1) * (z - z0) / h, n);
    });
  }
  return std::nullopt;
}

std::optional<opt::Halfspace<2>> primitive2(const ScadCall& c, const Matrix4& world, const std::string& where) {
  if (c.name == "circle") {
    const double r = radius_arg(c, "r", "d", 1, where);
    require_positive(r, c, "radius", where);
    const int n = fragments(c, r, where);
    return placed2({{-r, -r}, {r, r}}, world, [r, n](double x, double y) { return inside_ngon(x, y, r, n); });
  }
  if (c.name == "square") {
    const auto s = sizes_arg(c, "size", 2, 1, where);
    require_positive(s[0], c, "size", where);
    require_positive(s[1], c, "size", where);
    Box<2> b{{0, 0}, {s[0], s[1]}};
    if (bool_arg(c, "center")) b = {{-s[0] / 2, -s[1] / 2}, {s[0] / 2, s[1] / 2}};
    return placed2(b, world, [b](double x, double y) { return b.contains({x, y}); });
  }
  if (c.name == "polygon") {
    auto pts = polygon_points(c, where);
    auto paths = polygon_paths(c, pts.size(), where);
    Box<2> b{{INFINITY, INFINITY}, {-INFINITY, -INFINITY}};
    for (const auto& p : pts) b.include({{p[0], p[1]}, {p[0], p[1]}});
    return placed2(b, world, [pts, paths](double x, double y) { return inside_polygon(pts, paths, x, y); });
  }
  return std::nullopt;
}

opt::Halfspace<3> extrusion(const ScadCall& c, std::shared_ptr<const Solid2D> section, const Matrix4& world,
                            const std::string& where) {
  const Box<2> sb = section->bounds();
  if (c.name == "rotate_extrude") {
    const double angle = number_arg(c, "angle", 360, where);
    if (!(std::abs(angle) > 0)) throw InputError(where + ": rotate_extrude has an angle of 0");
    const double R = std::max(std::abs(sb.lo[0]), std::abs(sb.hi[0]));
    return placed3({{-R, -R, sb.lo[1]}, {R, R, sb.hi[1]}}, world, [=](double x, double y, double z) {
      double phi = std::atan2(y, x) * 180 / kPi;
      if (angle > 0 && phi < 0) phi += 360;
      if (angle < 0 && phi > 0) phi -= 360;
      if (std::abs(angle) < 360 && std::abs(phi) > std::abs(angle)) return false;
      return section->contains({std::hypot(x, y), z});
    });
  }
  const double h = number_arg(c, "height", 100, where);
  require_positive(h, c, "height", where);
  const double twist = number_arg(c, "twist", 0, where);
  const auto scale = sizes_arg(c, "scale", 2, 1, where);
  const double z0 = bool_arg(c, "center") ? -h / 2 : 0;
  const double smax = std::max({1.0, scale[0], scale[1]});
  Box<3> b{{sb.lo[0] * smax, sb.lo[1] * smax, z0}, {sb.hi[0] * smax, sb.hi[1] * smax, z0 + h}};
  for (int a = 0; a < 2; ++a) b.lo[a] = std::min(b.lo[a], sb.lo[a]), b.hi[a] = std::max(b.hi[a], sb.hi[a]);
  if (twist != 0) {
    const double R = smax * std::max({std::hypot(sb.lo[0], sb.lo[1]), std::hypot(sb.hi[0], sb.hi[1]),
                                      std::hypot(sb.lo[0], sb.hi[1]), std::hypot(sb.hi[0], sb.lo[1])});
    b.lo[0] = b.lo[1] = -R, b.hi[0] = b.hi[1] = R;
  }
  return placed3(b, world, [=](double x, double y, double z) {
    if (z < z0 || z > z0 + h) return false;
    const double f = (z - z0) / h;
    const double t = twist * f * kPi / 180, sx = 1 + (scale[0] - 1) * f, sy = 1 + (scale[1] - 1) * f;
    if (sx <= 0 || sy <= 0) return false;
    const double u = std::cos(t) * x - std::sin(t) * y, v = std::sin(t) * x + std::cos(t) * y;
    return section->contains({u / sx, v / sy});
  });
}

bool Solid2D::contains(const Point<2>& p) const { return opt::contains(tree, halfspaces, p); }

Box<2> Solid2D::bounds() const {
  Box<2> b{{0, 0}, {0, 0}};
  for (std::size_t i = 0; i < halfspaces.size(); ++i) {
    if (i == 0) b = halfspaces[i].bounds;
    else b.include(halfspaces[i].bounds);
  }
  return b;
}

}  // namespace csgfit::scad_shapes
