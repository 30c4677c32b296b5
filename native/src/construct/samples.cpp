#include "samples.h"

#include <algorithm>
#include <cmath>

#include "../features/patch_fit.h"
#include "csgfit/model/voxelize.h"
#include "model/linalg.h"
#include "model/random.h"

namespace csgfit::construct {

namespace {

using namespace linalg;

// Face samples stand this many vertex tolerances off their face: past the file's rounding.
constexpr double kOffsetTolerances = 4;
// ... and twice as far as the facets stray from the curved surface they tessellate (a chord's
// sagitta), so that a sample outside the facets is outside the surface too.
constexpr double kOffsetSagittas = 2;
// Never further than this share of the diagonal: a sample must stay beside its own face.
constexpr double kLongestOffset = 0.004;

Vec3 vertex(const TriangleMesh& m, int v) { return {m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}; }

void set_bit(Column& c, std::size_t i) { c[i / 64] |= 1ULL << (i % 64); }

void push_point(Samples& s, const Vec3& p, bool inside) {
  s.points.push_back(p);
  const std::size_t i = s.points.size() - 1;
  if (s.inside.size() <= i / 64) s.inside.resize(i / 64 + 1, 0);
  if (inside) set_bit(s.inside, i);
}

// How far the surface's facets stray from it (at their centroids and edge midpoints).
double sagitta(const MeshSurfaces& ms, const MeshSurface& s) {
  if (s.shape.kind == SurfaceKind::Plane) return 0;
  double worst = 0;
  for (int t : s.triangles) {
    const auto& tri = ms.mesh.triangles[t];
    const Vec3 a = vertex(ms.mesh, tri[0]), b = vertex(ms.mesh, tri[1]), c = vertex(ms.mesh, tri[2]);
    for (const Vec3& q : {scale(add(add(a, b), c), 1.0 / 3), scale(add(a, b), 0.5), scale(add(b, c), 0.5), scale(add(c, a), 0.5)})
      worst = std::max(worst, std::abs(surface_distance(s.shape, q)));
  }
  return worst;
}

// Voxel centres over the part's box with the voxeliser's labels, padded to whole words.
void add_volume_samples(const MeshSurfaces& ms, const SampleOptions& o, Samples& out) {
  const MeshReport r = analyze_mesh(ms.mesh);
  double box = 1, longest = 0;
  for (int a = 0; a < 3; ++a) longest = std::max(longest, r.bbox_max[a] - r.bbox_min[a]);
  for (int a = 0; a < 3; ++a) box *= std::max(r.bbox_max[a] - r.bbox_min[a], longest / 64);
  VoxelizeOptions v;
  v.voxel_size = std::cbrt(box / static_cast<double>(o.voxels));
  v.margin = 2;
  const VoxelGrid g = voxelize(ms.mesh, v);
  out.voxel = g.voxel_size();
  out.nx = g.nx(), out.ny = g.ny(), out.nz = g.nz();
  out.domain.lo = {g.origin_x(), g.origin_y(), g.origin_z()};
  out.domain.hi = {g.origin_x() + g.nx() * out.voxel, g.origin_y() + g.ny() * out.voxel, g.origin_z() + g.nz() * out.voxel};
  const std::size_t n = static_cast<std::size_t>(g.nx()) * g.ny() * g.nz();
  const std::size_t padded = (n + 63) / 64 * 64;
  out.points.reserve(padded);
  out.inside.assign(padded / 64, 0);
  out.real.assign(padded / 64, 0);
  for (int k = 0; k < g.nz(); ++k)
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) {
        const std::size_t at = out.points.size();
        out.points.push_back({g.center_x(i), g.center_y(j), g.center_z(k)});
        set_bit(out.real, at);
        if (g.get(i, j, k)) set_bit(out.inside, at);
      }
  while (out.points.size() < padded) out.points.push_back(out.domain.lo);
  out.face_word = out.points.size() / 64;
}

// Pairs of points on either side of the surface's triangles, `count` of them spread by area,
// each pair at least `offset` inside the triangle's edges (so that it stays beside this face).
void add_face_pairs(const MeshSurfaces& ms, const std::vector<int>& triangles, double area,
                    std::size_t count, double offset, rnd::Rng& rng, Samples& out) {
  if (!(area > 0)) return;
  std::vector<double> cumulative;
  double sum = 0;
  for (int t : triangles) {
    const auto& tri = ms.mesh.triangles[t];
    sum += 0.5 * norm(cross(sub(vertex(ms.mesh, tri[1]), vertex(ms.mesh, tri[0])), sub(vertex(ms.mesh, tri[2]), vertex(ms.mesh, tri[0]))));
    cumulative.push_back(sum);
  }
  for (std::size_t k = 0, tries = 0; k < count && tries < 8 * count; ++tries) {
    const double pick = rnd::uniform(rng, 0, 1) * sum;
    const std::size_t at = static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    const auto& tri = ms.mesh.triangles[triangles[std::min(at, triangles.size() - 1)]];
    const Vec3 a = vertex(ms.mesh, tri[0]), b = vertex(ms.mesh, tri[1]), c = vertex(ms.mesh, tri[2]);
    double u = rnd::uniform(rng, 0, 1), w = rnd::uniform(rng, 0, 1);
    if (u + w > 1) u = 1 - u, w = 1 - w;
    const Vec3 p = add(a, add(scale(sub(b, a), u), scale(sub(c, a), w)));
    const Vec3 n = normalized(cross(sub(b, a), sub(c, a)));
    // Distance to each edge: the point must be `offset` inside all three.
    bool clear = true;
    for (const auto& [e0, e1] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      const Vec3 e = sub(e1, e0);
      clear = clear && norm(cross(e, sub(p, e0))) / std::max(norm(e), 1e-300) >= 1.5 * offset;
    }
    if (!clear) continue;
    ++k;
    push_point(out, sub(p, scale(n, offset)), true);
    push_point(out, add(p, scale(n, offset)), false);
  }
}

// Voxel centres nearer a curved surface than its facets stray from it are on either side by
// the tessellation's whim, not the design's: they take no part (the face pairs speak there).
void drop_volume_samples_near(const MeshSurface& s, double band, Samples& out) {
  for (std::size_t w = 0; w < out.face_word; ++w)
    for (std::uint64_t bits = out.real[w]; bits; bits &= bits - 1) {
      const std::size_t i = w * 64 + static_cast<std::size_t>(__builtin_ctzll(bits));
      if (std::abs(surface_distance(s.shape, out.points[i])) < band) out.real[w] &= ~(1ULL << (i % 64));
    }
}

// A face beside a curved surface (a ledge around a polygonal boss, the floor of a rounded
// pocket) has face samples up to its edge, where the curve's facets and the round surface
// that stands for them disagree: they too are on either side by the tessellation's whim.
// first_pair: each surface's first face sample, and the end of the last; stray: each surface's
// sagitta. Only about the curve's own facets: its surface runs on past them, through faces it
// does not touch, whose samples may be all that tells two cells apart.
void drop_face_samples_near_curves(const MeshSurfaces& ms, const std::vector<std::size_t>& first_pair,
                                   const std::vector<double>& strays, Samples& out) {
  for (std::size_t c = 0; c < ms.surfaces.size(); ++c) {
    const MeshSurface& curve = ms.surfaces[c];
    const double stray = strays[c];
    if (!(stray > 0)) continue;
    Bounds3 near{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
    for (int t : curve.triangles)
      for (int v : ms.mesh.triangles[t])
        for (int a = 0; a < 3; ++a) {
          near.lo[a] = std::min(near.lo[a], ms.mesh.vertices[v][a] - 2 * stray);
          near.hi[a] = std::max(near.hi[a], ms.mesh.vertices[v][a] + 2 * stray);
        }
    for (std::size_t i = first_pair.front(); i < first_pair.back(); ++i) {
      if (i >= first_pair[c] && i < first_pair[c + 1]) continue;
      const Vec3& p = out.points[i];
      bool in_box = true;
      for (int a = 0; a < 3; ++a) in_box = in_box && p[a] >= near.lo[a] && p[a] <= near.hi[a];
      if (in_box && std::abs(surface_distance(curve.shape, p)) < stray) out.real[i / 64] &= ~(1ULL << (i % 64));
    }
  }
}

}  // namespace

Samples sample_part(const MeshSurfaces& ms, const SampleOptions& o) {
  Samples out;
  add_volume_samples(ms, o, out);
  double total_area = 0;
  for (const MeshSurface& s : ms.surfaces) total_area += s.area;
  rnd::Rng rng(rnd::splitmix(o.seed));
  const std::size_t before = out.points.size();
  std::vector<std::size_t> first_pair;  // per surface, its first face sample
  std::vector<double> strays;            // per surface, its sagitta
  for (const MeshSurface& s : ms.surfaces) {
    first_pair.push_back(out.points.size());
    const double floor_offset = kOffsetTolerances * ms.tolerance;
    const double stray = sagitta(ms, s);
    strays.push_back(stray);
    const double offset = std::min(std::max(floor_offset, kOffsetSagittas * stray), kLongestOffset * ms.diagonal);
    if (stray > 0) drop_volume_samples_near(s, offset, out);
    const auto count = std::max<std::size_t>(static_cast<std::size_t>(o.fewest_per_surface),
                                             static_cast<std::size_t>(static_cast<double>(o.face_samples) * s.area / std::max(total_area, 1e-300)));
    add_face_pairs(ms, s.triangles, s.area, count, offset, rng, out);
  }
  const std::size_t words = (out.points.size() + 63) / 64;
  out.inside.resize(words);
  out.real.resize(words, 0);
  for (std::size_t i = before; i < out.points.size(); ++i) set_bit(out.real, i);
  first_pair.push_back(out.points.size());
  drop_face_samples_near_curves(ms, first_pair, strays, out);
  for (std::size_t i = out.points.size(); i < words * 64; ++i) out.points.push_back(out.domain.lo);
  return out;
}

Column enclosed_empty(const Samples& s) {
  const auto solid = [&](int i, int j, int k) {
    const std::size_t at = (static_cast<std::size_t>(k) * s.ny + j) * s.nx + i;
    return (s.inside[at / 64] >> (at % 64)) & 1;
  };
  // The solid's reach along each lattice line, as coordinates: lines[axis][line] = {lo, hi}.
  const int n[3] = {s.nx, s.ny, s.nz};
  std::vector<std::pair<double, double>> reach[3];
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    reach[axis].assign(static_cast<std::size_t>(n[u]) * n[v], {1e300, -1e300});
    for (int b = 0; b < n[v]; ++b)
      for (int a = 0; a < n[u]; ++a)
        for (int t = 0; t < n[axis]; ++t) {
          int ijk[3];
          ijk[axis] = t, ijk[u] = a, ijk[v] = b;
          if (!solid(ijk[0], ijk[1], ijk[2])) continue;
          auto& r = reach[axis][static_cast<std::size_t>(b) * n[u] + a];
          const double c = s.domain.lo[axis] + (t + 0.5) * s.voxel;
          r.first = std::min(r.first, c), r.second = std::max(r.second, c);
        }
  }
  Column out(s.words(), 0);
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (((s.inside[i / 64] >> (i % 64)) & 1) || !((s.real[i / 64] >> (i % 64)) & 1)) continue;
    const Vec3& p = s.points[i];
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int a = static_cast<int>(std::floor((p[u] - s.domain.lo[u]) / s.voxel));
      const int b = static_cast<int>(std::floor((p[v] - s.domain.lo[v]) / s.voxel));
      if (a < 0 || b < 0 || a >= n[u] || b >= n[v]) continue;
      const auto& r = reach[axis][static_cast<std::size_t>(b) * n[u] + a];
      if (p[axis] > r.first && p[axis] < r.second) {
        set_bit(out, i);
        break;
      }
    }
  }
  return out;
}

Agreement agreement(const Node3D& tree, const Samples& s) {
  Agreement a;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (!((s.real[i / 64] >> (i % 64)) & 1)) continue;
    const bool solid = (s.inside[i / 64] >> (i % 64)) & 1;
    const Vec3& p = s.points[i];
    if (solid == contains(tree, p[0], p[1], p[2])) continue;
    const double w = i / 64 < s.face_word ? 1.0 : s.face_weight;
    (solid ? a.missed : a.extra) += w;
  }
  return a;
}

Column literal_column(const Literal& literal, const Samples& s) {
  Column c(s.words(), 0);
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (literal.contains(s.points[i])) set_bit(c, i);
  return c;
}

double weight_of(const Column& c, const Samples& s) {
  std::size_t volume = 0, face = 0;
  for (std::size_t w = 0; w < c.size(); ++w) (w < s.face_word ? volume : face) += static_cast<std::size_t>(__builtin_popcountll(c[w]));
  return static_cast<double>(volume) + s.face_weight * static_cast<double>(face);
}

}  // namespace csgfit::construct
