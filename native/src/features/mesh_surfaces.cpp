// The mesh's surfaces from its own triangles: facets (coplanar regions), then the cylinders
// their folds trace (features/facet_arcs.cpp), then surfaces of revolution among the rest
// (facet_revolutions.cpp), then the flat faces; the same surface met twice is one.
#include "csgfit/features/mesh_surfaces.h"

#include <algorithm>
#include <cmath>

#include "mesh_facets.h"
#include "model/linalg.h"
#include "patch_fit.h"

namespace csgfit {

namespace {

using namespace linalg;

// The largest fold of a regular polygon we read (a pentagon turns by 72 degrees per side).
constexpr double kPolygonFold = 72.5;
// A facet of a curved region nothing explains is still a flat face of its own when it holds this
// share of the region's area (a face beside a free-form fillet), not one strip of the curve.
constexpr double kFlatShare = 0.05;
// A segmentation has found the part's structure when this share of its area lies on surfaces
// of more than kFewTriangles triangle; else the tolerance grows kToleranceStep times, at most
// kCoarserTolerances times (2e-5 of the diagonal up to about 1e-2).
constexpr double kStructuredShare = 0.6;
constexpr std::size_t kFewTriangles = 1;
constexpr double kToleranceStep = 8;
constexpr int kCoarserTolerances = 3;

Vec3 vertex(const TriangleMesh& m, int v) { return {m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}; }

double diagonal_of(const TriangleMesh& m) {
  if (m.vertices.empty()) return 0;
  Vec3 lo = vertex(m, 0), hi = lo;
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], m.vertices[v][a]), hi[a] = std::max(hi[a], m.vertices[v][a]);
  return norm(sub(hi, lo));
}

void add_facet(const FacetMesh& fm, int f, MeshSurface& s) {
  s.triangles.insert(s.triangles.end(), fm.facets[f].triangles.begin(), fm.facets[f].triangles.end());
  s.area += fm.facets[f].area;
}

MeshSurface cylinder_of(const FacetMesh& fm, const FacetArc& arc) {
  MeshSurface s;
  s.shape.kind = SurfaceKind::Cylinder;
  s.shape.point = arc.centre;
  s.shape.axis = arc.axis;
  s.shape.radius = arc.radius;
  s.sides = arc.sides;
  s.vertex_direction = arc.vertex_direction;
  for (int f : arc.facets) add_facet(fm, f, s);
  return s;
}

MeshSurface plane_of(const FacetMesh& fm, int f) {
  MeshSurface s;
  s.shape.kind = SurfaceKind::Plane;
  s.shape.axis = fm.facets[f].normal;
  s.shape.point = scale(fm.facets[f].normal, fm.facets[f].offset);
  add_facet(fm, f, s);
  return s;
}

// Facets not yet explained, joined by folds up to `max_fold`: the curved regions left.
std::vector<std::vector<int>> smooth_groups(const FacetMesh& fm, const std::vector<char>& used, double max_fold) {
  std::vector<int> group_of(fm.facets.size(), -1);
  std::vector<std::vector<int>> groups;
  for (std::size_t s = 0; s < fm.facets.size(); ++s) {
    if (used[s] || group_of[s] >= 0) continue;
    std::vector<int> g{static_cast<int>(s)};
    group_of[s] = static_cast<int>(groups.size());
    for (std::size_t i = 0; i < g.size(); ++i)
      for (int k : fm.folds_of[g[i]]) {
        const Fold& fold = fm.folds[k];
        const int o = fold.a == g[i] ? fold.b : fold.a;
        if (used[o] || group_of[o] >= 0 || fold.degrees > max_fold) continue;
        group_of[o] = group_of[s];
        g.push_back(o);
      }
    groups.push_back(std::move(g));
  }
  return groups;
}

// The angle about the axis the triangles cover: 360 less the widest gap between their centroids.
double sweep_about_axis(const FacetMesh& fm, const MeshSurface& s) {
  const Vec3 d = s.shape.axis;
  const Vec3 u = normalized(reject(std::abs(d[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, d));
  const Vec3 w = cross(d, u);
  std::vector<double> angles;
  for (int t : s.triangles) {
    Vec3 c{0, 0, 0};
    for (int v : fm.mesh.triangles[t]) c = add(c, scale(vertex(fm.mesh, v), 1.0 / 3));
    const Vec3 r = reject(sub(c, s.shape.point), d);
    angles.push_back(std::atan2(dot(r, w), dot(r, u)));
  }
  if (angles.size() < 2) return 0;
  std::sort(angles.begin(), angles.end());
  double gap = angles.front() + 2 * M_PI - angles.back();
  for (std::size_t k = 0; k + 1 < angles.size(); ++k) gap = std::max(gap, angles[k + 1] - angles[k]);
  return (2 * M_PI - gap) * 180 / M_PI;
}

// Orientation and extent from the surface's own triangles: a plane's normal out of the solid, a
// curved surface's side (the solid inside it or outside), the reach along its axis, the largest
// distance of a vertex from it.
void settle(const FacetMesh& fm, MeshSurface& s) {
  double outward = 0;
  s.lo = 1e300, s.hi = -1e300;
  s.shape.rms = 0;
  for (int t : s.triangles) {
    Vec3 c{0, 0, 0};
    for (int v : fm.mesh.triangles[t]) {
      const Vec3 p = vertex(fm.mesh, v);
      c = add(c, scale(p, 1.0 / 3));
      const double along = dot(sub(p, s.shape.point), s.shape.axis);
      s.lo = std::min(s.lo, along), s.hi = std::max(s.hi, along);
      s.shape.rms = std::max(s.shape.rms, std::abs(surface_distance(s.shape, p)));
    }
    outward += fm.triangle_areas[t] * dot(fm.triangle_normals[t], surface_normal(s.shape, c));
  }
  if (s.shape.kind == SurfaceKind::Plane) {
    if (outward < 0) s.shape.axis = scale(s.shape.axis, -1);
    s.shape.convex = true;
  } else {
    s.shape.convex = outward > 0;
    if (s.shape.kind != SurfaceKind::Sphere) s.sweep = sweep_about_axis(fm, s);
  }
}

bool same_surface(const MeshSurface& a, const MeshSurface& b, double tol) {
  const SurfacePatch &p = a.shape, &q = b.shape;
  if (p.kind != q.kind || p.convex != q.convex || a.sides != b.sides) return false;
  if (p.kind == SurfaceKind::Plane)
    return dot(p.axis, q.axis) > 1 - 1e-9 && std::abs(dot(sub(q.point, p.point), p.axis)) <= tol;
  if (p.kind == SurfaceKind::Cylinder) {
    const bool on_axis = norm(cross(p.axis, q.axis)) <= 1e-6 && norm(reject(sub(q.point, p.point), p.axis)) <= tol;
    // One polygon's vertices are 360 / n apart: any two of them name the same phase.
    const double turn = std::atan2(dot(cross(a.vertex_direction, b.vertex_direction), p.axis),
                                   dot(a.vertex_direction, b.vertex_direction));
    const double step = a.sides > 0 ? 2 * M_PI / a.sides : 1;
    const bool same_phase = a.sides == 0 || std::abs(std::remainder(turn, step)) <= 1e-4;
    return on_axis && same_phase && std::abs(p.radius - q.radius) <= tol;
  }
  return false;  // spheres, cones and tori come whole from one profile
}

void merge_duplicates(const FacetMesh& fm, std::vector<MeshSurface>& surfaces, double tol) {
  std::vector<MeshSurface> kept;
  for (MeshSurface& s : surfaces) {
    auto twin = std::find_if(kept.begin(), kept.end(), [&](const MeshSurface& k) { return same_surface(k, s, tol); });
    if (twin == kept.end()) {
      kept.push_back(std::move(s));
      continue;
    }
    twin->triangles.insert(twin->triangles.end(), s.triangles.begin(), s.triangles.end());
    twin->area += s.area;
    settle(fm, *twin);
  }
  surfaces = std::move(kept);
}

// A flat facet whose vertices lie on a curved surface it touches nearly tangentially is that
// surface's tessellation, not a face (the polygon OpenSCAD closes a sphere's pole with); a
// cylinder's cap also has its vertices on the cylinder, but stands across it.
void absorb_pole_caps(const FacetMesh& fm, std::vector<MeshSurface>& found, std::vector<char>& used,
                      double max_fold, double tol) {
  const double tangent = std::cos(max_fold * M_PI / 180);
  for (std::size_t f = 0; f < fm.facets.size(); ++f) {
    if (used[f]) continue;
    const Facet& facet = fm.facets[f];
    Vec3 c{0, 0, 0};
    for (int v : facet.vertices) c = add(c, scale(vertex(fm.mesh, v), 1.0 / static_cast<double>(facet.vertices.size())));
    for (MeshSurface& s : found) {
      if (s.shape.kind == SurfaceKind::Plane || s.shape.kind == SurfaceKind::Cylinder) continue;
      if (std::abs(dot(facet.normal, surface_normal(s.shape, c))) < tangent) continue;
      bool on = true;
      for (int v : facet.vertices) on = on && std::abs(surface_distance(s.shape, vertex(fm.mesh, v))) <= tol;
      if (!on) continue;
      add_facet(fm, static_cast<int>(f), s);
      used[f] = 1;
      break;
    }
  }
}

// The segmentation at one tolerance (model units).
MeshSurfaces segment_at(const TriangleMesh& mesh, double tol, const MeshSurfaceOptions& options) {
  MeshSurfaces out;
  out.diagonal = diagonal_of(mesh);
  out.tolerance = tol;
  const FacetMesh fm = build_facets(mesh, tol);
  std::vector<char> used(fm.facets.size(), 0);
  std::vector<MeshSurface> found;
  // Surfaces of revolution first: a ball's or a torus's columns of facets also fold about one
  // direction each and would pass for narrow cylinders.
  for (const auto& group : smooth_groups(fm, used, options.smooth_fold_degrees))
    if (group.size() >= 4)
      for (MeshSurface& s : find_revolutions(fm, group, tol, used)) found.push_back(std::move(s));
  // Then cylinders about other axes where they meet (two crossed bores), and prisms whose
  // sides fold by more than a smooth surface does (hexagons, octagons).
  for (const FacetArc& arc : find_facet_arcs(fm, used, 2 * tol, std::max(options.smooth_fold_degrees, kPolygonFold))) {
    // The turns between the arc's own facets: a round surface's are small.
    double widest = 0;
    for (int f : arc.facets)
      for (int k : fm.folds_of[f]) {
        const int other = fm.folds[k].a == f ? fm.folds[k].b : fm.folds[k].a;
        if (std::find(arc.facets.begin(), arc.facets.end(), other) != arc.facets.end())
          widest = std::max(widest, fm.folds[k].degrees);
      }
    if (arc.sides == 0 && widest > options.smooth_fold_degrees) continue;  // flat faces on a circle by chance
    found.push_back(cylinder_of(fm, arc));
    for (int f : arc.facets) used[f] = 1;
  }
  absorb_pole_caps(fm, found, used, options.smooth_fold_degrees, 2 * tol);
  for (const auto& group : smooth_groups(fm, used, options.smooth_fold_degrees)) {
    double area = 0;
    for (int f : group) area += fm.facets[f].area;
    for (int f : group) {
      if (group.size() == 1 || fm.facets[f].area >= kFlatShare * area) {
        found.push_back(plane_of(fm, f));
      } else {
        out.unexplained.insert(out.unexplained.end(), fm.facets[f].triangles.begin(), fm.facets[f].triangles.end());
      }
      used[f] = 1;
    }
  }
  for (MeshSurface& s : found) settle(fm, s);
  merge_duplicates(fm, found, 2 * tol);
  out.surfaces = std::move(found);
  out.mesh = fm.mesh;
  return out;
}

// The share of the surface that lies on surfaces of more than a few triangles: how much
// structure a segmentation found (on a noisy mesh every triangle is a plane of its own).
double structured_share(const MeshSurfaces& s) {
  double structured = 0, total = 0;
  for (const MeshSurface& m : s.surfaces) {
    total += m.area;
    if (m.triangles.size() > kFewTriangles) structured += m.area;
  }
  return total > 0 ? structured / total : 0;
}

}  // namespace

MeshSurfaces segment_mesh_surfaces(const TriangleMesh& mesh, const MeshSurfaceOptions& options) {
  const double diagonal = diagonal_of(mesh);
  double tol = std::max(options.tolerance * diagonal, 1e-12);
  MeshSurfaces best = segment_at(mesh, tol, options);
  // A mesh that is not exact (a scan, a decimated or smoothed file) has faces only at a coarser
  // tolerance: try coarser ones while most of the surface has no structure.
  best.structured = structured_share(best);
  for (int step = 0; step < kCoarserTolerances && best.structured < kStructuredShare; ++step) {
    tol *= kToleranceStep;
    MeshSurfaces coarser = segment_at(mesh, tol, options);
    coarser.structured = structured_share(coarser);
    if (coarser.structured > best.structured) best = std::move(coarser);
  }
  return best;
}

}  // namespace csgfit
