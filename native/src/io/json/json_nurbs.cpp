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

// The reader evaluates z = S(x, y) by inverting x(u) and y(v) alone: the net must be a grid
// whose columns keep one x and rows one y, strictly increasing from one side of the rectangle
// 'size' to the other (any spacing: Greville, equal, a designer's own).
BSplineSurface height_field_of(BSplineBasis u, BSplineBasis v, const std::vector<Vec3>& points,
                               const std::vector<double>& size, const std::string& where) {
  const int nu = u.count(), nv = v.count();
  const double tol = 1e-6 * std::max(size[0], size[1]);
  std::vector<double> xs(nu), ys(nv), heights;
  for (int i = 0; i < nu; ++i) xs[i] = points[i][0];
  for (int j = 0; j < nv; ++j) ys[j] = points[static_cast<std::size_t>(nu) * j][1];
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Vec3& c = points[i + static_cast<std::size_t>(nu) * j];
      if (std::fabs(c[0] - xs[i]) > tol || std::fabs(c[1] - ys[j]) > tol)
        fail(where, "control points must form a grid: one x per column, one y per row");
      heights.push_back(c[2]);
    }
  if (std::fabs(xs.front() + size[0] / 2) > tol || std::fabs(xs.back() - size[0] / 2) > tol ||
      std::fabs(ys.front() + size[1] / 2) > tol || std::fabs(ys.back() - size[1] / 2) > tol)
    fail(where, "the control net's end columns and rows must be the sides of the rectangle 'size'");
  xs.front() = -size[0] / 2, xs.back() = size[0] / 2, ys.front() = -size[1] / 2, ys.back() = size[1] / 2;
  try {
    return BSplineSurface::height_field(std::move(u), std::move(v), std::move(xs), std::move(ys), heights);
  } catch (const std::invalid_argument&) {
    fail(where, "control columns and rows must be strictly increasing in x and y");
  }
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
    std::vector<Vec3> points;
    for (const ojson& c : net) {
      if (!c.is_array() || c.size() != 3) fail(where, "a control point must be [x, y, z]");
      points.push_back({finite_entry(c[0], "control_points", where),
                        finite_entry(c[1], "control_points", where),
                        finite_entry(c[2], "control_points", where)});
    }
    BSplineSurface s = height_field_of(std::move(u), std::move(v), points, size, where);
    const Primitive3D placed = Primitive3D::nurbs(p.cx, p.cy, p.cz, std::move(s), p.rotation);
    p.patch = placed.patch;
    p.dims = placed.dims;
  } catch (const std::invalid_argument& e) {
    fail(where, e.what());
  }
}

}  // namespace csgfit::json_detail
