#include "io/json/json_nurbs.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace csgfit::json_detail {

namespace {

const ojson& array_field(const ojson& j, const char* key, const std::string& where) {
  const ojson* v = member(j, key);
  if (!v || !v->is_array()) fail(where, std::string("'") + key + "' must be an array");
  return *v;
}

double finite_entry(const ojson& v, const char* key, const std::string& where) {
  if (!v.is_number()) fail(where, std::string("'") + key + "' must hold numbers");
  return finite_field(v.get<double>(), where, key, kNotFinite3D);
}

std::vector<double> numbers(const ojson& j, const char* key, const std::string& where) {
  std::vector<double> out;
  for (const ojson& v : array_field(j, key, where)) out.push_back(finite_entry(v, key, where));
  return out;
}

// A small count from an array of two (degree, counts): bounded so that a hostile file cannot
// ask for a huge net.
std::pair<int, int> two_counts(const ojson& j, const char* key, int lo, int hi, const std::string& where) {
  const ojson& a = array_field(j, key, where);
  if (a.size() != 2 || !a[0].is_number_integer() || !a[1].is_number_integer())
    fail(where, std::string("'") + key + "' must be two integers");
  const long long u = a[0].get<long long>(), v = a[1].get<long long>();
  if (u < lo || u > hi || v < lo || v > hi)
    fail(where, std::string("'") + key + "' must lie in " + std::to_string(lo) + ".." + std::to_string(hi));
  return {static_cast<int>(u), static_cast<int>(v)};
}

}  // namespace

void write_nurbs_fields(const Primitive3D& p, const std::string& where, ojson& j) {
  if (!p.patch) fail(where, "a nurbs leaf has no patch");
  const BSplineSurface& s = *p.patch;
  j["size"] = {p.dims[0], p.dims[1], p.dims[2]};
  j["degree"] = {s.u_basis().degree(), s.v_basis().degree()};
  j["counts"] = {s.u_basis().count(), s.v_basis().count()};
  j["knots_u"] = s.u_basis().knots();
  j["knots_v"] = s.v_basis().knots();
  ojson net = ojson::array();
  for (const Vec3& c : s.net()) {
    for (double v : c) finite_field(v, where, "control_points", kNotFinite3D);
    net.push_back({c[0], c[1], c[2]});
  }
  j["control_points"] = std::move(net);
}

void read_nurbs_fields(const ojson& j, const std::string& where, Primitive3D& p) {
  const auto degree = two_counts(j, "degree", 1, kMaxBSplineDegree, where);
  const auto counts = two_counts(j, "counts", 2, 1000, where);
  const std::vector<double> size = numbers(j, "size", where);
  if (size.size() < 2 || !(size[0] > 0) || !(size[1] > 0))
    fail(where, "'size' must start with the rectangle's two positive sizes");
  const ojson& net = array_field(j, "control_points", where);
  const std::size_t n = static_cast<std::size_t>(counts.first) * static_cast<std::size_t>(counts.second);
  if (net.size() != n) fail(where, "'control_points' must hold counts[0] x counts[1] points");
  try {
    BSplineBasis u(numbers(j, "knots_u", where), degree.first);
    BSplineBasis v(numbers(j, "knots_v", where), degree.second);
    if (u.count() != counts.first || v.count() != counts.second)
      fail(where, "the knot vectors do not fit 'counts' and 'degree'");
    std::vector<double> heights;
    std::vector<Vec3> points;
    for (const ojson& c : net) {
      if (!c.is_array() || c.size() != 3) fail(where, "a control point must be [x, y, z]");
      points.push_back({finite_entry(c[0], "control_points", where),
                        finite_entry(c[1], "control_points", where),
                        finite_entry(c[2], "control_points", where)});
      heights.push_back(points.back()[2]);
    }
    const XYRectangle rect{-size[0] / 2, size[0] / 2, -size[1] / 2, size[1] / 2};
    BSplineSurface s = BSplineSurface::height_field(u, v, rect, heights);
    // The reader evaluates z = S(x, y) straight from x and y: the net must be the grid.
    const double tol = 1e-6 * std::max(size[0], size[1]);
    for (std::size_t i = 0; i < n; ++i)
      if (std::fabs(points[i][0] - s.net()[i][0]) > tol || std::fabs(points[i][1] - s.net()[i][1]) > tol)
        fail(where, "control points must lie on the Greville grid of the rectangle 'size'");
    const Primitive3D placed = Primitive3D::nurbs(p.cx, p.cy, p.cz, std::move(s), p.rotation);
    p.patch = placed.patch;
    p.dims = placed.dims;
  } catch (const std::invalid_argument& e) {
    fail(where, e.what());
  }
}

}  // namespace csgfit::json_detail
