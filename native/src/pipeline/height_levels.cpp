#include "pipeline/height_levels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "csgfit/pipeline/fit_bitmap.h"

namespace csgfit {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

// The highest point over each cell of an x-y raster; NaN where no point reaches the cell.
struct TopRaster {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, cell = 1;
  int close = 1;          // the closing's radius in cells
  std::size_t speck = 4;  // the most cells of a hole that is a gap between points
  std::vector<double> top;
  // The highest point within half a spacing: a face's own cells, which no wall carves away.
  std::vector<double> near_top;
  // Points on walls (normal within 30 degrees of horizontal): x, y, the unit outward normal in
  // x-y and z. A footprint ends at its walls, however far the closing reaches.
  struct Wall {
    double x, y, nx, ny, z;
  };
  std::vector<Wall> walls;
  double carve = 0;  // how far outside a wall the footprint is carved
  double at(int i, int j) const { return top[static_cast<std::size_t>(i + nx * j)]; }
};

// Calls fn(cell, dx, dy) for each cell whose centre lies within `radius` of (x, y), (dx, dy)
// the offset of its centre from that point.
template <class Fn>
void for_cells_within(const TopRaster& r, double x, double y, double radius, Fn fn) {
  const int span = static_cast<int>(std::ceil(radius / r.cell));
  const int ci = static_cast<int>((x - r.x0) / r.cell), cj = static_cast<int>((y - r.y0) / r.cell);
  for (int j = std::max(0, cj - span); j <= std::min(r.ny - 1, cj + span); ++j)
    for (int i = std::max(0, ci - span); i <= std::min(r.nx - 1, ci + span); ++i) {
      const double dx = r.x0 + (i + 0.5) * r.cell - x, dy = r.y0 + (j + 0.5) * r.cell - y;
      if (dx * dx + dy * dy <= radius * radius) fn(static_cast<std::size_t>(i + r.nx * j), dx, dy);
    }
}

// Raises `grid`'s cells whose centres lie within `reach` of p to p's height.
void reach_cells(const TopRaster& r, std::vector<double>& grid, const Vec3& p, double reach) {
  for_cells_within(r, p[0], p[1], reach, [&](std::size_t c, double, double) {
    if (!(grid[c] >= p[2])) grid[c] = p[2];
  });
}

TopRaster top_raster(const PointTarget& t) {
  const Bounds3 b = bounds_of(t.points);
  const double extent = std::max(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1]);
  TopRaster r;
  // Two cells per point spacing, at most 128 a side (where the bitmap fit is quick): a point
  // reaches the cells within 0.8 spacings, which widens a face by about the third of a spacing
  // its last row of points lies inside its edge.
  r.cell = std::max(0.5 * t.spacing, extent / 128);
  r.x0 = b.lo[0] - 2 * r.cell, r.y0 = b.lo[1] - 2 * r.cell;
  r.nx = static_cast<int>(std::ceil((b.hi[0] - b.lo[0]) / r.cell)) + 4;
  r.ny = static_cast<int>(std::ceil((b.hi[1] - b.lo[1]) / r.cell)) + 4;
  r.top.assign(static_cast<std::size_t>(r.nx) * r.ny, kNaN);
  // A scan from above samples a grid; one all around is sampled at random, with gaps of twice
  // the mean spacing between the points of a face.
  const double gaps = t.scan == ScanKind::Top ? 1.0 : 2.0;
  // Far enough to join the random points of a face all around; the walls end what overshoots.
  const double reach = std::max((t.scan == ScanKind::Top ? 0.8 : 1.5) * t.spacing, r.cell);
  r.close = std::max(1, static_cast<int>(std::lround(gaps * t.spacing / r.cell)));
  r.carve = reach + r.close * r.cell;
  // Holes narrower than four spacings (a disc of radius two) are no features the points resolve.
  const double speck_area = 4 * kPi * t.spacing * t.spacing;
  r.speck = std::max<std::size_t>(4, static_cast<std::size_t>(speck_area / (r.cell * r.cell)));
  r.near_top.assign(r.top.size(), kNaN);
  for (std::size_t k = 0; k < t.points.size(); ++k) {
    const Vec3& p = t.points[k];
    const Vec3& n = t.normals[k];
    const double horizontal = std::hypot(n[0], n[1]);
    if (n[2] < 0.5 && horizontal > 0.85) r.walls.push_back({p[0], p[1], n[0] / horizontal, n[1] / horizontal, p[2]});
    // A wall's or an underside's point is not the top of its column (scans all around).
    if (n[2] < 0.5) continue;
    reach_cells(r, r.top, p, reach);
    reach_cells(r, r.near_top, p, std::max(0.5 * t.spacing, 0.75 * r.cell));
  }
  return r;
}

// The heights of the flat faces that look up: clusters of the z of points whose normal is
// within 6 degrees of +z (the bottom of a dimple is not a face), highest first, each held by
// enough points to be a face.
std::vector<double> flat_levels(const PointTarget& t, double floor, double tol) {
  std::vector<double> z;
  for (std::size_t i = 0; i < t.points.size(); ++i)
    if (t.normals[i][2] > 0.995 && t.points[i][2] > floor + tol) z.push_back(t.points[i][2]);
  std::sort(z.begin(), z.end());
  const std::size_t least = std::max<std::size_t>(20, t.points.size() / 100);
  std::vector<double> levels;
  for (std::size_t a = 0, b = 0; a < z.size(); a = b) {
    for (b = a + 1; b < z.size() && z[b] - z[b - 1] <= tol;) ++b;
    if (b - a >= least) levels.push_back(z[(a + b) / 2]);
  }
  std::reverse(levels.begin(), levels.end());
  if (levels.size() > 8) levels.resize(8);
  return levels;
}

// Dilation (grow) or erosion of a cell mask by a disc of `radius` cells.
std::vector<char> morph(const std::vector<char>& in, int nx, int ny, int radius, bool grow) {
  std::vector<char> out(in.size(), grow ? 0 : 1);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      bool hit = !grow;
      for (int dj = -radius; dj <= radius && hit != grow; ++dj)
        for (int di = -radius; di <= radius && hit != grow; ++di) {
          if (di * di + dj * dj > radius * radius) continue;
          const int a = i + di, b = j + dj;
          const bool v = a >= 0 && b >= 0 && a < nx && b < ny && in[static_cast<std::size_t>(a + nx * b)];
          if (grow ? v : !v) hit = grow;
        }
      out[static_cast<std::size_t>(i + nx * j)] = hit;
    }
  return out;
}

bool at_lower_level(double top, double h, double tol, const std::vector<double>& levels) {
  if (std::isnan(top)) return true;  // nothing seen: the table through a hole
  for (double l : levels)
    if (l < h - tol && std::fabs(top - l) <= tol) return true;
  return false;
}

// Clears the cells just outside the walls below level h (which bound its footprint) that no
// point of a face at or above h covers itself: what the reach and the closing add past an edge.
void carve_outside_walls(const TopRaster& r, double h, double tol, std::vector<char>& mask) {
  for (const TopRaster::Wall& w : r.walls) {
    if (w.z > h - tol) continue;
    for_cells_within(r, w.x, w.y, r.carve, [&](std::size_t c, double dx, double dy) {
      if (!(r.near_top[c] >= h - tol) && dx * w.nx + dy * w.ny > 0) mask[c] = 0;
    });
  }
}

// Where the part reaches level h. An enclosed hole stays a hole when its bottom is flat (a
// pocket, a lower level, the table); one whose bottom is curved (a dimple) is filled, for a
// detected primitive to cut; specks are gaps between the points.
Bitmap footprint(const TopRaster& r, double h, double tol, const std::vector<double>& levels,
                 bool& filled_curved) {
  std::vector<char> mask(r.top.size());
  for (std::size_t c = 0; c < mask.size(); ++c) mask[c] = r.top[c] >= h - tol;
  // A closing by a spacing: the gaps between the points of one face go, straight edges stay.
  mask = morph(morph(mask, r.nx, r.ny, r.close, true), r.nx, r.ny, r.close, false);
  carve_outside_walls(r, h, tol, mask);
  Bitmap b(r.nx, r.ny);
  const auto set = [&](int i, int j) { b.set(i, r.ny - 1 - j); };
  const auto inside = [&](int i, int j) { return b.get(i, r.ny - 1 - j); };
  for (int j = 0; j < r.ny; ++j)
    for (int i = 0; i < r.nx; ++i)
      if (mask[static_cast<std::size_t>(i + r.nx * j)]) set(i, j);
  std::vector<char> seen(static_cast<std::size_t>(r.nx) * r.ny, 0);
  for (int sj = 0; sj < r.ny; ++sj)
    for (int si = 0; si < r.nx; ++si) {
      if (inside(si, sj) || seen[static_cast<std::size_t>(si + r.nx * sj)]) continue;
      std::vector<std::pair<int, int>> hole{{si, sj}};
      seen[static_cast<std::size_t>(si + r.nx * sj)] = 1;
      bool border = false;
      std::size_t flat = 0;
      for (std::size_t k = 0; k < hole.size(); ++k) {
        const auto [i, j] = hole[k];
        border = border || i == 0 || j == 0 || i == r.nx - 1 || j == r.ny - 1;
        flat += at_lower_level(r.at(i, j), h, tol, levels) ? 1 : 0;
        const int next[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
        for (const auto& n : next) {
          if (n[0] < 0 || n[1] < 0 || n[0] >= r.nx || n[1] >= r.ny || inside(n[0], n[1])) continue;
          char& s = seen[static_cast<std::size_t>(n[0] + r.nx * n[1])];
          if (!s) s = 1, hole.push_back({n[0], n[1]});
        }
      }
      const bool curved = 2 * flat < hole.size(), speck = hole.size() <= r.speck;
      if (border || (!speck && !curved)) continue;
      filled_curved = filled_curved || (!speck && curved);
      for (const auto& [i, j] : hole) set(i, j);
    }
  return b;
}

// A 2D primitive of the footprint (pixel units, y up) as the solid over it from floor to h.
Primitive3D extruded(const Primitive& p, const TopRaster& r, double floor, double h) {
  const double x = r.x0 + r.cell * p.cx, y = r.y0 + r.cell * p.cy, zc = 0.5 * (floor + h);
  const Quaternion turn = Quaternion::from_axis_angle(0, 0, 1, p.angle);
  switch (p.kind) {
    case PrimitiveKind::Rectangle: return Primitive3D::box(x, y, zc, r.cell * p.w, r.cell * p.h, h - floor, turn);
    case PrimitiveKind::Triangle:
      return Primitive3D::prism(x, y, zc, r.cell * p.w, r.cell * p.h, h - floor, p.apex, turn);
    case PrimitiveKind::Circle:
    case PrimitiveKind::Ellipse: break;
  }
  return Primitive3D::cylinder(x, y, zc, 0.25 * r.cell * (p.w + p.h), h - floor);
}

Node3D extruded(const Node& n, const TopRaster& r, double floor, double h) {
  if (n.kind == NodeKind::Primitive) return Node3D::leaf(extruded(n.primitive, r, floor, h));
  std::vector<Node3D> children;
  for (const Node& c : n.children) children.push_back(extruded(c, r, floor, h));
  return Node3D::op(n.kind, std::move(children));
}

// What a detected tree subtracts that no extrusion makes: spheres, cones, tori, ellipsoids
// and cylinders that do not stand upright.
void curved_negatives(const Node3D& n, bool subtracted, std::vector<Node3D>& out) {
  if (n.kind == NodeKind::Primitive) {
    const Primitive3D& p = n.primitive;
    const bool upright = std::fabs(p.rotation.matrix()[2][2]) > 0.99;
    const bool curved = p.kind == PrimitiveKind3D::Sphere || p.kind == PrimitiveKind3D::Cone ||
                        p.kind == PrimitiveKind3D::Torus || p.kind == PrimitiveKind3D::Ellipsoid ||
                        (p.kind == PrimitiveKind3D::Cylinder && !upright);
    if (subtracted && curved) out.push_back(n);
    return;
  }
  for (std::size_t i = 0; i < n.children.size(); ++i)
    curved_negatives(n.children[i], subtracted || (n.kind == NodeKind::Difference && i > 0), out);
}

// The footprints' kinds are the extrusions of the kinds the search may use.
PrimitiveSet footprint_kinds(const PrimitiveSet3D& allowed) {
  PrimitiveSet s{0};
  if (allowed.has(PrimitiveKind3D::Box)) s.add(PrimitiveKind::Rectangle);
  if (allowed.has(PrimitiveKind3D::Cylinder)) s.add(PrimitiveKind::Circle);
  if (allowed.has(PrimitiveKind3D::TriangularPrism)) s.add(PrimitiveKind::Triangle);
  return s;
}

}  // namespace

std::vector<Node3D> level_trees(const PointTarget& target, const std::vector<Node3D>& detected,
                                const LevelOptions& o, const std::atomic<bool>* cancel) {
  const TopRaster raster = top_raster(target);
  const double tol = 0.02 * std::max(target.top - o.floor, 1e-9);
  const std::vector<double> levels = flat_levels(target, o.floor, tol);
  if (levels.empty()) return {};
  FitOptions fit;
  fit.primitives = footprint_kinds(o.primitives);
  if (fit.primitives.empty()) return {};
  fit.time_limit = std::max(0.3, o.seconds / static_cast<double>(levels.size()));
  fit.threads = o.threads;
  fit.seed = o.seed;
  std::vector<Node3D> pieces;
  bool filled_curved = false;
  Bitmap above(raster.nx, raster.ny);
  for (double h : levels) {
    if (cancel && cancel->load()) break;
    try {
      const Bitmap b = footprint(raster, h, tol, levels, filled_curved);
      // A level that reaches no further than the one above adds nothing to the union.
      const std::size_t more = b.count() - std::min(b.count(), above.count());
      if (more <= b.count() / 200) continue;
      above = b;
      pieces.push_back(extruded(fit_bitmap(b, fit, nullptr, cancel).tree, raster, o.floor, h));
    } catch (const std::invalid_argument&) {
      // A level whose footprint is empty or too small for the bitmap fit adds nothing.
    }
  }
  if (pieces.empty()) return {};
  const Node3D levels_tree = pieces.size() == 1 ? pieces.front() : Node3D::op(NodeKind::Union, pieces);
  std::vector<Node3D> out{levels_tree};
  if (!filled_curved) return out;
  for (const Node3D& d : detected) {
    std::vector<Node3D> cut{levels_tree};
    curved_negatives(d, false, cut);
    if (cut.size() > 1) out.push_back(Node3D::op(NodeKind::Difference, std::move(cut)));
  }
  return out;
}

}  // namespace csgfit
