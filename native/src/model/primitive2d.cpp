#include "csgfit/model/primitive2d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "model/interval.h"

namespace csgfit {

namespace {

using interval::clip_halfline;
using interval::clip_linear;
using interval::Interval;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
// Sizes below this are not meaningful on a pixel grid and would make the search waste time on
// invisible primitives; it also keeps the moment and distance formulas away from zero.
constexpr double kMinSize = 0.25;
// A general triangle with its apex further out than this is a sliver no designer would draw.
constexpr double kMaxApex = 4.0;

// What scan conversion needs of a primitive, computed once rather than once per row.
struct SpanSetup {
  const Primitive& p;
  double c, s;                              // cos and sin of the angle
  std::array<std::array<double, 2>, 3> t{};  // triangle vertices
  explicit SpanSetup(const Primitive& prim)
      : p(prim), c(std::cos(prim.angle * kDegToRad)), s(std::sin(prim.angle * kDegToRad)) {
    if (p.kind == PrimitiveKind::Triangle) t = p.triangle_vertices();
  }
};

// The x interval of the primitive on the horizontal line at height y.
Interval span_at(const SpanSetup& q, double y) {
  const Primitive& p = q.p;
  const double c = q.c, s = q.s;
  Interval iv;
  const double v = y - p.cy;
  switch (p.kind) {
    case PrimitiveKind::Rectangle:
      // local x = c*u + s*v, local y = -s*u + c*v with u = x - cx.
      clip_linear(iv, c, s * v - c * p.cx, -p.w / 2, p.w / 2);
      clip_linear(iv, -s, c * v + s * p.cx, -p.h / 2, p.h / 2);
      return iv;
    case PrimitiveKind::Circle:
    case PrimitiveKind::Ellipse: {
      const double ia = 4.0 / (p.w * p.w);
      const double ib = 4.0 / (p.h * p.h);
      const double qa = c * c * ia + s * s * ib;
      const double qb = 2 * c * s * v * (ia - ib);
      const double qc = v * v * (s * s * ia + c * c * ib) - 1.0;
      const double disc = qb * qb - 4 * qa * qc;
      if (disc < 0) return Interval{1, 0};
      const double root = std::sqrt(disc);
      return Interval{p.cx + (-qb - root) / (2 * qa), p.cx + (-qb + root) / (2 * qa)};
    }
    case PrimitiveKind::Triangle: {
      for (int i = 0; i < 3; ++i) {
        const auto& a = q.t[i];
        const auto& b = q.t[(i + 1) % 3];
        // cross(b - a, q - a) >= 0 for q = (x, y): linear in x.
        const double ex = b[0] - a[0], ey = b[1] - a[1];
        clip_halfline(iv, -ey, ex * (y - a[1]) + ey * a[0]);
      }
      return iv;
    }
  }
  return iv;
}

double wrap_degrees(double a, double period) {
  a = std::fmod(a, period);
  if (a < 0) a += period;
  return a;
}

}  // namespace

std::string_view to_string(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::Rectangle: return "rectangle";
    case PrimitiveKind::Circle: return "circle";
    case PrimitiveKind::Ellipse: return "ellipse";
    case PrimitiveKind::Triangle: return "triangle";
  }
  return "?";
}

PrimitiveKind primitive_kind_from_string(std::string_view name) {
  if (name == "rectangle" || name == "rect" || name == "square") return PrimitiveKind::Rectangle;
  if (name == "circle") return PrimitiveKind::Circle;
  if (name == "ellipse") return PrimitiveKind::Ellipse;
  if (name == "triangle") return PrimitiveKind::Triangle;
  throw std::invalid_argument("unknown primitive '" + std::string(name) +
                              "' (expected rectangle, circle, ellipse or triangle)");
}

PrimitiveSet PrimitiveSet::parse(std::string_view list) {
  PrimitiveSet set{0};
  std::size_t pos = 0;
  while (pos <= list.size()) {
    const std::size_t comma = std::min(list.find(',', pos), list.size());
    std::string_view item = list.substr(pos, comma - pos);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    if (item == "all")
      set = all();
    else if (!item.empty())
      set.add(primitive_kind_from_string(item));
    pos = comma + 1;
  }
  if (set.empty()) throw std::invalid_argument("the primitive list is empty");
  // Rectangles are what every decomposition bottoms out in (seed 003's bounding boxes).
  return set;
}

Primitive Primitive::rectangle(double cx, double cy, double w, double h, double angle) {
  Primitive p{PrimitiveKind::Rectangle, cx, cy, w, h, angle, 0};
  p.normalize();
  return p;
}
Primitive Primitive::circle(double cx, double cy, double r) {
  Primitive p{PrimitiveKind::Circle, cx, cy, 2 * r, 2 * r, 0, 0};
  p.normalize();
  return p;
}
Primitive Primitive::ellipse(double cx, double cy, double rx, double ry, double angle) {
  Primitive p{PrimitiveKind::Ellipse, cx, cy, 2 * rx, 2 * ry, angle, 0};
  p.normalize();
  return p;
}
Primitive Primitive::triangle(double cx, double cy, double w, double h, double angle, double apex) {
  Primitive p{PrimitiveKind::Triangle, cx, cy, w, h, angle, apex};
  p.normalize();
  return p;
}

double Primitive::area() const {
  switch (kind) {
    case PrimitiveKind::Rectangle: return w * h;
    case PrimitiveKind::Circle:
    case PrimitiveKind::Ellipse: return kPi * w * h / 4.0;
    case PrimitiveKind::Triangle: return w * h / 2.0;
  }
  return 0;
}

std::array<std::array<double, 2>, 3> Primitive::triangle_vertices() const {
  const double c = std::cos(angle * kDegToRad);
  const double s = std::sin(angle * kDegToRad);
  const double local[3][2] = {{-w / 2, -h / 2}, {w / 2, -h / 2}, {apex * w / 2, h / 2}};
  std::array<std::array<double, 2>, 3> out{};
  for (int i = 0; i < 3; ++i)
    out[i] = {cx + c * local[i][0] - s * local[i][1], cy + s * local[i][0] + c * local[i][1]};
  return out;
}

bool Primitive::contains(double x, double y) const {
  const Interval iv = span_at(SpanSetup(*this), y);
  return !iv.empty() && x >= iv.lo && x <= iv.hi;
}

double Primitive::signed_distance(double x, double y) const {
  const double c = std::cos(angle * kDegToRad);
  const double s = std::sin(angle * kDegToRad);
  const double u = x - cx, v = y - cy;
  const double lx = c * u + s * v;
  const double ly = -s * u + c * v;
  switch (kind) {
    case PrimitiveKind::Rectangle: {
      const double qx = std::fabs(lx) - w / 2, qy = std::fabs(ly) - h / 2;
      const double outside = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
      return outside + std::min(std::max(qx, qy), 0.0);
    }
    case PrimitiveKind::Circle: return std::hypot(u, v) - w / 2;
    case PrimitiveKind::Ellipse: {
      // Gradient-normalised implicit value: exact on the boundary, first order near it.
      const double a = w / 2, b = h / 2;
      const double f = (lx * lx) / (a * a) + (ly * ly) / (b * b) - 1.0;
      const double gx = 2 * lx / (a * a), gy = 2 * ly / (b * b);
      const double g = std::hypot(gx, gy);
      if (g < 1e-12) return -std::min(a, b);
      return f / g;
    }
    case PrimitiveKind::Triangle: {
      const auto t = triangle_vertices();
      double best = std::numeric_limits<double>::infinity();
      bool inside = true;
      for (int i = 0; i < 3; ++i) {
        const auto& a = t[i];
        const auto& b = t[(i + 1) % 3];
        const double ex = b[0] - a[0], ey = b[1] - a[1];
        const double px = x - a[0], py = y - a[1];
        const double len2 = ex * ex + ey * ey;
        const double tt = std::clamp((px * ex + py * ey) / len2, 0.0, 1.0);
        best = std::min(best, std::hypot(px - tt * ex, py - tt * ey));
        if (ex * py - ey * px < 0) inside = false;
      }
      return inside ? -best : best;
    }
  }
  return 0;
}

void Primitive::normalize() {
  w = std::max(std::fabs(w), kMinSize);
  h = std::max(std::fabs(h), kMinSize);
  switch (kind) {
    case PrimitiveKind::Circle:
      w = h = 0.5 * (w + h);
      angle = 0;
      apex = 0;
      break;
    case PrimitiveKind::Rectangle:
    case PrimitiveKind::Ellipse:
      angle = wrap_degrees(angle, 180.0);
      apex = 0;
      break;
    case PrimitiveKind::Triangle:
      angle = wrap_degrees(angle, 360.0);
      apex = std::clamp(apex, -kMaxApex, kMaxApex);
      break;
  }
}

bool Primitive::operator==(const Primitive& o) const {
  return kind == o.kind && cx == o.cx && cy == o.cy && w == o.w && h == o.h && angle == o.angle &&
         apex == o.apex;
}

void row_range(const Primitive& p, int height, int& row_begin, int& row_end) {
  const double c = std::cos(p.angle * kDegToRad);
  const double s = std::sin(p.angle * kDegToRad);
  double ymin, ymax;
  if (p.kind == PrimitiveKind::Triangle) {
    const auto t = p.triangle_vertices();
    ymin = std::min({t[0][1], t[1][1], t[2][1]});
    ymax = std::max({t[0][1], t[1][1], t[2][1]});
  } else {
    const double a = p.w / 2, b = p.h / 2;
    const double half = (p.kind == PrimitiveKind::Rectangle)
                            ? std::fabs(a * s) + std::fabs(b * c)
                            : std::sqrt(a * a * s * s + b * b * c * c);
    ymin = p.cy - half;
    ymax = p.cy + half;
  }
  const double hgt = static_cast<double>(height);
  if (!std::isfinite(ymin) || !std::isfinite(ymax) || !std::isfinite(p.cx)) {
    row_begin = row_end = 0;  // a NaN parameter draws nothing rather than undefined rows
    return;
  }
  const double first = std::ceil(hgt - 0.5 - ymax - 1e-9);
  const double last = std::floor(hgt - 0.5 - ymin + 1e-9);
  row_begin = static_cast<int>(std::clamp(first, 0.0, hgt));
  row_end = static_cast<int>(std::clamp(last + 1, 0.0, hgt));
  if (!(row_begin < row_end)) row_begin = row_end = 0;
}

void rasterize(const Primitive& p, Bitmap& out) {
  out.clear();
  rasterize_into(p, out);
}

void rasterize_into(const Primitive& p, Bitmap& out) {
  int r0, r1;
  row_range(p, out.height(), r0, r1);
  const double width = static_cast<double>(out.width());
  const SpanSetup setup(p);
  for (int r = r0; r < r1; ++r) {
    const double y = out.height() - r - 0.5;
    const Interval iv = span_at(setup, y);
    if (iv.empty()) continue;
    // Pixel col is inside when its centre col + 0.5 lies in [lo, hi].
    const double c0 = std::max(std::ceil(iv.lo - 0.5), 0.0);
    const double c1 = std::min(std::floor(iv.hi - 0.5), width - 1);
    if (c0 <= c1) out.set_span(r, static_cast<int>(c0), static_cast<int>(c1) + 1);
  }
}

}  // namespace csgfit
