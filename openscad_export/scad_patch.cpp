#include "scad_patch.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "scad_format.h"

namespace csgfit::scad {

namespace {

constexpr int kMaxCells = 256;

struct Grid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, dx = 0, dy = 0, floor_gap = 0;
  std::vector<double> top;  ///< (nx + 1) x (ny + 1) heights, x fastest
  double x(int i) const { return x0 + i * dx; }
  double y(int j) const { return y0 + j * dy; }
  double at(int i, int j) const { return top[static_cast<std::size_t>(i + (nx + 1) * j)]; }
};

Grid sample(const BSplineSurface& s, int nx, int ny) {
  const XYRectangle& r = s.rectangle();
  Grid g{nx, ny, r.x0, r.y0, (r.x1 - r.x0) / nx, (r.y1 - r.y0) / ny, 0, {}};
  g.floor_gap = 1e-4 * std::max(r.x1 - r.x0, r.y1 - r.y0);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) g.top.push_back(std::max(s.height_at(g.x(i), g.y(j)), g.floor_gap));
  return g;
}

// Each cell is split along its diagonal (i, j)-(i + 1, j + 1); the triangles' heights at the
// cell centre and the edge midpoints are compared with the patch's.
double deviation(const BSplineSurface& s, const Grid& g) {
  double worst = 0;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double a = g.at(i, j), b = g.at(i + 1, j), c = g.at(i, j + 1), d = g.at(i + 1, j + 1);
      const double xm = g.x(i) + g.dx / 2, ym = g.y(j) + g.dy / 2;
      const double probes[4][3] = {{xm, ym, (a + d) / 2}, {xm, g.y(j), (a + b) / 2},
                                   {g.x(i), ym, (a + c) / 2}, {g.x(i) + g.dx * 0.75, g.y(j) + g.dy * 0.25,
                                                               0.5 * b + 0.25 * a + 0.25 * d}};
      for (const auto& p : probes) worst = std::max(worst, std::fabs(s.height_at(p[0], p[1]) - p[2]));
    }
  return worst;
}

std::string points_code(const Grid& g, int decimals) {
  std::string out = "points = [";
  auto point = [&](double x, double y, double z) {
    out += "[" + number(x, decimals) + ", " + number(y, decimals) + ", " + number(z, decimals) + "], ";
  };
  for (int j = 0; j <= g.ny; ++j)
    for (int i = 0; i <= g.nx; ++i) point(g.x(i), g.y(j), g.at(i, j));
  for (int j = 0; j <= g.ny; ++j)
    for (int i = 0; i <= g.nx; ++i) point(g.x(i), g.y(j), 0);
  out.resize(out.size() - 2);
  return out + "]";
}

// Faces wound clockwise seen from outside, as OpenSCAD's polyhedron wants them.
std::string faces_code(const Grid& g) {
  const int row = g.nx + 1, bottom = row * (g.ny + 1);
  auto top = [&](int i, int j) { return i + row * j; };
  std::string out = "faces = [";
  auto face = [&](std::initializer_list<int> v) {
    out += "[";
    for (int k : v) out += std::to_string(k) + ", ";
    out.resize(out.size() - 2);
    out += "], ";
  };
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const int a = top(i, j), b = top(i + 1, j), c = top(i, j + 1), d = top(i + 1, j + 1);
      face({a, d, b}), face({a, c, d});
      face({bottom + a, bottom + b, bottom + d}), face({bottom + a, bottom + d, bottom + c});
    }
  for (int i = 0; i < g.nx; ++i) {
    const int s0 = top(i, 0), s1 = top(i + 1, 0), n0 = top(i, g.ny), n1 = top(i + 1, g.ny);
    face({s0, s1, bottom + s1, bottom + s0});
    face({n1, n0, bottom + n0, bottom + n1});
  }
  for (int j = 0; j < g.ny; ++j) {
    const int w0 = top(0, j), w1 = top(0, j + 1), e0 = top(g.nx, j), e1 = top(g.nx, j + 1);
    face({w1, w0, bottom + w0, bottom + w1});
    face({e0, e1, bottom + e1, bottom + e0});
  }
  out.resize(out.size() - 2);
  return out + "]";
}

}  // namespace

PatchPolyhedron patch_polyhedron(const BSplineSurface& patch, double tolerance, int decimals) {
  const XYRectangle& r = patch.rectangle();
  const double aspect = (r.x1 - r.x0) / (r.y1 - r.y0);
  // Start at about four cells per knot span and double until the tolerance holds.
  int nx = std::max(4, 4 * (patch.u_basis().count() - patch.u_basis().degree()));
  int ny = std::max(4, 4 * (patch.v_basis().count() - patch.v_basis().degree()));
  nx = std::max(nx, static_cast<int>(ny * aspect / 4));
  ny = std::max(ny, static_cast<int>(nx / aspect / 4));
  Grid g = sample(patch, std::min(nx, kMaxCells), std::min(ny, kMaxCells));
  double dev = deviation(patch, g);
  while (dev > tolerance && (g.nx < kMaxCells || g.ny < kMaxCells)) {
    g = sample(patch, std::min(2 * g.nx, kMaxCells), std::min(2 * g.ny, kMaxCells));
    dev = deviation(patch, g);
  }
  PatchPolyhedron out;
  out.cells_x = g.nx, out.cells_y = g.ny, out.deviation = dev;
  out.code = "polyhedron(" + points_code(g, decimals) + ", " + faces_code(g) + ", convexity = 4);";
  return out;
}

}  // namespace csgfit::scad
