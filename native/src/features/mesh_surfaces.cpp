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
  }
}

bool same_surface(const MeshSurface& a, const MeshSurface& b, double tol) {
  const SurfacePatch &p = a.shape, &q = b.shape;
  if (p.kind != q.kind || p.convex != q.convex || a.sides != b.sides) return false;
  if (p.kind == SurfaceKind::Plane)
    return dot(p.axis, q.axis) > 1 - 1e-9 && std::abs(dot(sub(q.point, p.point), p.axis)) <= tol;
  if (p.kind == SurfaceKind::Cylinder) {
    const bool on_axis = norm(cross(p.axis, q.axis)) <= 1e-6 && norm(reject(sub(q.point, p.point), p.axis)) <= tol;
    const bool same_phase = a.sides == 0 || norm(cross(a.vertex_direction, b.vertex_direction)) <= 1e-4;
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

}  // namespace

MeshSurfaces segment_mesh_surfaces(const TriangleMesh& mesh, const MeshSurfaceOptions& options) {
  MeshSurfaces out;
  out.diagonal = diagonal_of(mesh);
  out.tolerance = std::max(options.tolerance * out.diagonal, 1e-12);
  const double tol = out.tolerance;
  const FacetMesh fm = build_facets(mesh, tol);
  std::vector<char> used(fm.facets.size(), 0);
  std::vector<MeshSurface> found;
  // Surfaces of revolution first: a ball's or a torus's columns of facets also fold about one
  // direction each and would pass for narrow cylinders.
  for (const auto& group : smooth_groups(fm, used, options.smooth_fold_degrees))
    if (group.size() >= 4)
      for (MeshSurface& s : find_revolutions(fm, group, tol, used)) found.push_back(std::move(s));
  // Then prisms whose sides fold by more than a smooth surface does (hexagons, octagons).
  for (const FacetArc& arc : find_facet_arcs(fm, used, 2 * tol, std::max(options.smooth_fold_degrees, kPolygonFold))) {
    if (arc.sides == 0) continue;  // flat faces on a circle by chance
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
  return out;
}

}  // namespace csgfit
