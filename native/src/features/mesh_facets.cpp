#include "mesh_facets.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "model/linalg.h"

namespace csgfit {

namespace {

using namespace linalg;
using EdgeKey = std::pair<int, int>;

Vec3 at(const TriangleMesh& m, int v) { return {m.vertices[v][0], m.vertices[v][1], m.vertices[v][2]}; }

// Triangles around each undirected edge, in file order.
std::map<EdgeKey, std::vector<int>> edge_triangles(const TriangleMesh& m) {
  std::map<EdgeKey, std::vector<int>> edges;
  for (int t = 0; t < static_cast<int>(m.triangles.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
      if (a != b) edges[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  return edges;
}

// The solid's own orientation: pieces made consistent, and the whole turned outwards when the
// mesh encloses negative volume (an inside-out file).
TriangleMesh welded_outwards(const TriangleMesh& mesh) {
  TriangleMesh m = mesh;
  weld_vertices(m);
  repair_orientation(m);
  if (signed_volume(m) < 0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// Grows one facet from `seed` over manifold edges while every vertex of the next triangle lies
// within `tolerance` of the seed's plane and the triangle faces the same way.
void grow_facet(FacetMesh& fm, int seed, int id, double tolerance,
                const std::map<EdgeKey, std::vector<int>>& edges) {
  const Vec3 n = fm.triangle_normals[seed];
  const double d = dot(n, at(fm.mesh, fm.mesh.triangles[seed][0]));
  std::vector<int> stack{seed};
  fm.facet_of[seed] = id;
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    fm.facets[id].triangles.push_back(t);
    for (int k = 0; k < 3; ++k) {
      const int a = fm.mesh.triangles[t][k], b = fm.mesh.triangles[t][(k + 1) % 3];
      const auto it = edges.find({std::min(a, b), std::max(a, b)});
      if (it == edges.end() || it->second.size() != 2) continue;
      for (int u : it->second) {
        if (fm.facet_of[u] != -2) continue;
        bool flat = dot(fm.triangle_normals[u], n) > 0;
        for (int v : fm.mesh.triangles[u]) flat = flat && std::abs(dot(n, at(fm.mesh, v)) - d) <= tolerance;
        if (!flat) continue;
        fm.facet_of[u] = id;
        stack.push_back(u);
      }
    }
  }
}

// The plane of a facet from its own triangles: area-weighted normal, mean offset of its vertices.
void fit_facet_plane(FacetMesh& fm, Facet& f) {
  Vec3 n{0, 0, 0};
  for (int t : f.triangles) {
    n = add(n, scale(fm.triangle_normals[t], fm.triangle_areas[t]));
    f.area += fm.triangle_areas[t];
    for (int v : fm.mesh.triangles[t]) f.vertices.push_back(v);
  }
  std::sort(f.vertices.begin(), f.vertices.end());
  f.vertices.erase(std::unique(f.vertices.begin(), f.vertices.end()), f.vertices.end());
  f.normal = normalized(n);
  double sum = 0;
  for (int v : f.vertices) sum += dot(f.normal, at(fm.mesh, v));
  f.offset = sum / static_cast<double>(f.vertices.size());
}

// One fold per pair of facets that share manifold edges.
void find_folds(FacetMesh& fm, const std::map<EdgeKey, std::vector<int>>& edges) {
  struct Shared {
    double length = 0, longest = 0;
    Vec3 direction{0, 0, 1}, first{0, 0, 0};
    bool straight = true, convex = true;
    int uses = 0;
  };
  std::map<EdgeKey, Shared> shared;
  for (const auto& [edge, tris] : edges) {
    if (tris.size() != 2) continue;
    const int fa = fm.facet_of[tris[0]], fb = fm.facet_of[tris[1]];
    if (fa < 0 || fb < 0 || fa == fb) continue;
    const Vec3 p = at(fm.mesh, edge.first), q = at(fm.mesh, edge.second);
    const double len = norm(sub(q, p));
    Shared& s = shared[{std::min(fa, fb), std::max(fa, fb)}];
    const Vec3 dir = normalized(sub(q, p));
    if (s.uses > 0 && norm(cross(dir, s.direction)) > 1e-3) s.straight = false;
    if (s.uses > 0 && norm(cross(sub(p, s.first), s.direction)) > 1e-3 * (len + norm(sub(p, s.first)))) s.straight = false;
    if (len > s.longest) s.longest = len, s.direction = dir;
    if (s.uses == 0) s.first = p;
    s.length += len;
    ++s.uses;
    // Convex when the other facet's far vertex lies behind this facet's plane.
    const Facet& a = fm.facets[fa];
    for (int v : fm.mesh.triangles[tris[1]])
      if (v != edge.first && v != edge.second) s.convex = dot(a.normal, at(fm.mesh, v)) - a.offset < 0;
  }
  for (const auto& [pair, s] : shared) {
    Fold f;
    f.a = pair.first, f.b = pair.second;
    f.direction = s.direction;
    f.point = s.first;
    f.length = s.length;
    f.straight = s.straight;
    f.convex = s.convex;
    const double c = std::clamp(dot(fm.facets[f.a].normal, fm.facets[f.b].normal), -1.0, 1.0);
    f.degrees = std::acos(c) * 180 / M_PI;
    fm.folds_of[f.a].push_back(static_cast<int>(fm.folds.size()));
    fm.folds_of[f.b].push_back(static_cast<int>(fm.folds.size()));
    fm.folds.push_back(f);
  }
}

}  // namespace

FacetMesh build_facets(const TriangleMesh& mesh, double tolerance) {
  FacetMesh fm;
  fm.mesh = welded_outwards(mesh);
  const std::size_t n = fm.mesh.triangles.size();
  fm.triangle_normals.resize(n);
  fm.triangle_areas.resize(n);
  fm.facet_of.assign(n, -2);  // -2: not yet visited
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = fm.mesh.triangles[t];
    const Vec3 c = cross(sub(at(fm.mesh, tri[1]), at(fm.mesh, tri[0])), sub(at(fm.mesh, tri[2]), at(fm.mesh, tri[0])));
    fm.triangle_areas[t] = 0.5 * norm(c);
    fm.triangle_normals[t] = normalized(c);
    // A sliver has no trustworthy normal: it joins no facet and no fold.
    if (!(fm.triangle_areas[t] > tolerance * tolerance)) fm.facet_of[t] = -1;
  }
  const auto edges = edge_triangles(fm.mesh);
  for (std::size_t t = 0; t < n; ++t) {
    if (fm.facet_of[t] != -2) continue;
    fm.facets.emplace_back();
    grow_facet(fm, static_cast<int>(t), static_cast<int>(fm.facets.size()) - 1, tolerance, edges);
  }
  for (Facet& f : fm.facets) fit_facet_plane(fm, f);
  fm.folds_of.resize(fm.facets.size());
  find_folds(fm, edges);
  return fm;
}

std::vector<int> facet_vertices(const FacetMesh& fm, const std::vector<int>& facets) {
  std::vector<int> out;
  for (int f : facets) out.insert(out.end(), fm.facets[f].vertices.begin(), fm.facets[f].vertices.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace csgfit
