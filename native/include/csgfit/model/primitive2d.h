// 2D primitives: rectangle, circle, ellipse, triangle; their exact scan conversion at pixel
// centres, areas and signed distances.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "csgfit/model/bitmap.h"

namespace csgfit {

enum class PrimitiveKind { Rectangle, Circle, Ellipse, Triangle };

/// Canonical lower-case name ("rectangle", "circle", "ellipse", "triangle").
std::string_view to_string(PrimitiveKind kind);
/// Parses a name as written by to_string (also "rect"); throws std::invalid_argument.
PrimitiveKind primitive_kind_from_string(std::string_view name);

/// Bit set of primitive kinds a fit may use.
struct PrimitiveSet {
  unsigned bits = 0xF;
  bool has(PrimitiveKind k) const { return bits & (1u << static_cast<unsigned>(k)); }
  void add(PrimitiveKind k) { bits |= 1u << static_cast<unsigned>(k); }
  bool empty() const { return bits == 0; }
  static PrimitiveSet all() { return PrimitiveSet{0xF}; }
  /// Parses "rectangle,circle,..." (also "all"); throws std::invalid_argument naming the bad item.
  static PrimitiveSet parse(std::string_view list);
};

/// One primitive in the solver's frame: pixel units, y up, angles in degrees counter-clockwise.
///
/// In its local frame (centre at the origin, rotated by `angle`) every kind spans
/// [-w/2, w/2] x [-h/2, h/2]:
///  - Rectangle: that box.
///  - Ellipse: the ellipse with semi-axes w/2, h/2. A Circle is an ellipse with w == h (the
///    solver keeps them equal; `angle` is ignored).
///  - Triangle: base from (-w/2, -h/2) to (w/2, -h/2) and apex at (apex * w/2, h/2). apex = 0
///    is the isosceles triangle of seed 003, apex = +-1 the right-angled ones; any other value is
///    a general triangle.
struct Primitive {
  PrimitiveKind kind = PrimitiveKind::Rectangle;
  double cx = 0, cy = 0;
  double w = 1, h = 1;
  double angle = 0;
  double apex = 0;

  static Primitive rectangle(double cx, double cy, double w, double h, double angle = 0);
  static Primitive circle(double cx, double cy, double r);
  static Primitive ellipse(double cx, double cy, double rx, double ry, double angle = 0);
  static Primitive triangle(double cx, double cy, double w, double h, double angle = 0,
                            double apex = 0);

  /// Exact area of the continuous shape.
  double area() const;
  /// Triangle vertices in the solver's frame (counter-clockwise); only for triangles.
  std::array<std::array<double, 2>, 3> triangle_vertices() const;
  /// Signed distance from (x, y) to the boundary: negative inside. Exact for rectangles,
  /// circles and triangles; for ellipses a first-order estimate that is exact on the boundary.
  double signed_distance(double x, double y) const;
  /// Whether the point lies inside (boundary counts as inside), the test scan conversion uses.
  bool contains(double x, double y) const;
  /// Keeps sizes positive and circle sizes equal; called after every parameter change.
  void normalize();
  bool operator==(const Primitive& o) const;
};

/// Scan-converts p into `out` (which must already have the canvas size): a pixel is set exactly
/// when its centre lies inside p. Clears `out` first.
void rasterize(const Primitive& p, Bitmap& out);
/// rasterize() without the clearing: sets p's pixels and leaves every other bit as it was (the
/// incremental evaluator clears only the rows it is about to redraw).
void rasterize_into(const Primitive& p, Bitmap& out);

/// The rows [row_begin, row_end) that may hold pixels of p on a canvas of the given height.
void row_range(const Primitive& p, int height, int& row_begin, int& row_end);

}  // namespace csgfit
