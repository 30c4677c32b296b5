// Circular arcs and straight segments of a bitmap's boundary: the circles, holes and edges a
// designer drew, read off the contour instead of guessed from the distance map.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/bitmap.h"

namespace csgfit {

/// A point of the sub-pixel contour (solver frame, pixel units) with its outward unit normal.
struct ContourPoint {
  double x = 0, y = 0;
  double nx = 0, ny = 0;
};

/// The 0.5 level set of the shape blurred by a Gaussian of one pixel: one point where it
/// crosses the segment between two neighbouring pixel centres, the normal from the blurred
/// gradient. The blur turns the staircase of a slanted or round edge into a smooth curve.
std::vector<ContourPoint> subpixel_contour(const Bitmap& mask);

/// A bitmap's sub-pixel contour and the larger side of its canvas (the largest radius a reading
/// may have): computed once, read by each of the readings below.
struct Contour {
  std::vector<ContourPoint> points;
  double canvas = 0;
};
Contour contour_of(const Bitmap& mask);

/// A circle that part of the contour lies on. `hole` when the shape lies outside it (a concave
/// arc: the circle is to be cut), a disc of the shape otherwise.
struct BoundaryArc {
  double cx = 0, cy = 0, r = 0;
  bool hole = false;
  double coverage = 0;      ///< fraction of the circle's length the contour follows
  std::size_t support = 0;  ///< contour points on it
};

/// The circles the contour follows for at least a quarter of their length (within a
/// pixel's fraction, normals agreeing), found by RANSAC on contour points with normals and
/// refined by least squares; radii between 2.5 px and the canvas size. Each point explains at
/// most one arc. Deterministic; at most `limit`, best supported first.
std::vector<BoundaryArc> boundary_arcs(const Contour& contour, std::size_t limit = 16);
std::vector<BoundaryArc> boundary_arcs(const Bitmap& mask, std::size_t limit = 16);

/// A straight segment of the contour: the shape lies on the side n . p <= offset of its line
/// (n the outward unit normal), and the contour follows the line for t in [t0, t1] along the
/// tangent (-ny, nx).
struct BoundaryLine {
  double nx = 0, ny = 0, offset = 0;
  double t0 = 0, t1 = 0;
  std::size_t support = 0;  ///< contour points on it
};

/// The straight segments of the contour at least 6 px long (points within 0.5 px,
/// normals agreeing), found by RANSAC and refined by total least squares. Each point explains
/// at most one segment. Deterministic; at most `limit`, longest first.
std::vector<BoundaryLine> boundary_lines(const Contour& contour, std::size_t limit = 16);
std::vector<BoundaryLine> boundary_lines(const Bitmap& mask, std::size_t limit = 16);

/// An ellipse that part of the contour lies on (angle: of the rx axis, degrees in [0, 180)).
struct BoundaryEllipse {
  double cx = 0, cy = 0, rx = 0, ry = 0, angle = 0;
  bool hole = false;
  double coverage = 0;      ///< fraction of the ellipse's parameter the contour follows
  std::size_t support = 0;  ///< contour points on it
};

/// The ellipses (not circles: the axes differ by more than 4 % and no circle follows the points
/// as closely) the contour follows for at least a quarter of their parameter, with at
/// most half their points on one of `arcs` or `lines` that lies mostly off the ellipse (a flat
/// ellipse can bridge a disc's arc and the straight edge it meets). RANSAC on conics through five points whose
/// normals agree, refined by algebraic least squares; semi-axes from 2.5 px to the canvas size.
/// Deterministic; at most `limit`, best supported first.
std::vector<BoundaryEllipse> boundary_ellipses(const Contour& contour, const std::vector<BoundaryArc>& arcs,
                                               const std::vector<BoundaryLine>& lines,
                                               std::size_t limit = 8);

}  // namespace csgfit
