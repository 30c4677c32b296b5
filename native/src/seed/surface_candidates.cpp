#include "csgfit/seed/surface_candidates.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

// The primitives whose kind `kinds` allows, their adjacency and points re-indexed.
void keep_allowed(RecognisedPrimitives& rec, const PrimitiveSet3D& kinds) {
  std::vector<int> index(rec.primitives.size(), -1);
  RecognisedPrimitives kept;
  for (std::size_t i = 0; i < rec.primitives.size(); ++i) {
    if (!kinds.has(rec.primitives[i].primitive.kind)) continue;
    index[i] = static_cast<int>(kept.primitives.size());
    kept.primitives.push_back(std::move(rec.primitives[i]));
    kept.patch_points.push_back(std::move(rec.patch_points[i]));
  }
  kept.adjacent.resize(kept.primitives.size());
  for (std::size_t i = 0; i < index.size(); ++i) {
    if (index[i] < 0) continue;
    for (int j : rec.adjacent[i])
      if (index[static_cast<std::size_t>(j)] >= 0)
        kept.adjacent[static_cast<std::size_t>(index[i])].push_back(index[static_cast<std::size_t>(j)]);
  }
  rec = std::move(kept);
}

// Whether model point p lies in a set voxel of g.
bool solid_at(const VoxelGrid& g, const Vec3& p) {
  const double h = g.voxel_size();
  const int i = static_cast<int>(std::floor((p[0] - g.origin_x()) / h));
  const int j = static_cast<int>(std::floor((p[1] - g.origin_y()) / h));
  const int k = static_cast<int>(std::floor((p[2] - g.origin_z()) / h));
  if (i < 0 || j < 0 || k < 0 || i >= g.nx() || j >= g.ny() || k >= g.nz()) return false;
  return g.get(i, j, k);
}

// The halfspace whose boundary is the plane of `face`, on its outer side (`in_front`: what a
// cut that left the face removed) or behind it, as a box through all of `part`.
SignedPrimitive halfspace_cut(const SurfacePatch& face, const Bounds3& part, bool in_front) {
  const Vec3 n = in_front ? face.axis : scale(face.axis, -1);
  const Vec3 u = normalized(reject(std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, n));
  const Vec3 w = cross(n, u);
  const Vec3 mid = scale(add(part.lo, part.hi), 0.5);
  const double reach = norm(sub(part.hi, part.lo));  // the part's box diagonal
  // From the plane out past the part along n, and twice the part across.
  const double depth = std::max(dot(sub(mid, face.point), n), 0.0) + reach;
  const Vec3 centre = add(add(face.point, scale(n, depth / 2)),
                          add(scale(u, dot(sub(mid, face.point), u)), scale(w, dot(sub(mid, face.point), w))));
  Mat3 m;
  for (int r = 0; r < 3; ++r) m[r] = {n[r], u[r], w[r]};
  SignedPrimitive cut;
  cut.positive = false;
  cut.conjectured = true;
  cut.halfspace = true;
  cut.primitive = Primitive3D::box(centre[0], centre[1], centre[2], depth, 2 * reach, 2 * reach,
                                   quaternion_from_matrix(m));
  return cut;
}

}  // namespace

double point_spacing(const std::vector<Vec3>& points) {
  if (points.size() < 2) return 0;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 400);
  std::vector<double> nearest;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    double best = 1e300;
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i) best = std::min(best, squared(sub(points[i], points[j])));
    nearest.push_back(std::sqrt(best));
  }
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

SurfaceDetectOptions detector_for(SurfaceDetectOptions d, const PrimitiveSet3D& kinds) {
  d.spheres = d.spheres && kinds.has(PrimitiveKind3D::Sphere);
  d.cylinders = d.cylinders && kinds.has(PrimitiveKind3D::Cylinder);
  d.cones = d.cones && kinds.has(PrimitiveKind3D::Cone);
  d.tori = d.tori && kinds.has(PrimitiveKind3D::Torus);
  return d;
}

SurfaceReading read_surface(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                            const SurfaceDetectOptions& detect, const PrimitiveSet3D& kinds,
                            std::uint64_t seed, const std::atomic<bool>* cancel) {
  SurfaceReading out;
  out.diagonal = part_diagonal(points);
  out.patches = detect_surfaces(points, normals, detector_for(detect, kinds), seed, cancel);
  // Two patches touch across the band that their edges lose (normals blend there and those
  // points belong to neither): a few point spacings, and no less than 2 % of the part.
  out.contact = std::max(0.02 * out.diagonal, 6 * point_spacing(points));
  RecognisedPrimitives rec = recognise_primitives(out.patches, points, out.diagonal, out.contact);
  keep_allowed(rec, kinds);
  out.recognised = rec.primitives;
  out.graph = build_precedence_graph(std::move(rec.primitives), rec.adjacent, rec.patch_points);
  return out;
}

std::vector<SignedPrimitive> surface_proposals(const SurfaceReading& reading,
                                               const std::vector<Vec3>& points,
                                               const PrimitiveSet3D& kinds) {
  std::vector<SignedPrimitive> pool;
  add_distinct(pool, reading.recognised, reading.diagonal);
  if (points.empty() || !kinds.has(PrimitiveKind3D::Box)) return pool;
  const Bounds3 part = bounds_of(points);
  std::vector<int> planes;
  for (std::size_t k = 0; k < reading.patches.size(); ++k)
    if (reading.patches[k].kind == SurfaceKind::Plane && !reading.patches[k].points.empty())
      planes.push_back(static_cast<int>(k));
  // Seed 002's reading of a few faces alone: one face is a slab as deep as the part, two or
  // three perpendicular neighbours on a convex corner a block.
  const auto read_alone = [&](std::vector<int> faces) {
    std::vector<SurfacePatch> subset;
    for (int k : faces) subset.push_back(reading.patches[k]);
    add_distinct(pool, recognise_primitives(subset, points, reading.diagonal, reading.contact).primitives,
                 reading.diagonal);
  };
  for (int k : planes) {
    read_alone({k});
    std::vector<SignedPrimitive> cuts;
    for (bool in_front : {true, false}) cuts.push_back(halfspace_cut(reading.patches[k], part, in_front));
    add_distinct(pool, cuts, reading.diagonal);
  }
  const auto adjacent = patch_adjacency(reading.patches, points, reading.contact);
  const auto corner = [&](int a, int b) {
    return std::abs(dot(reading.patches[a].axis, reading.patches[b].axis)) < 0.15 &&
           std::find(adjacent[a].begin(), adjacent[a].end(), b) != adjacent[a].end();
  };
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      if (!corner(planes[i], planes[j])) continue;
      read_alone({planes[i], planes[j]});
      for (std::size_t l = j + 1; l < planes.size(); ++l)
        if (corner(planes[i], planes[l]) && corner(planes[j], planes[l]))
          read_alone({planes[i], planes[j], planes[l]});
    }
  return pool;
}

bool alike(const SignedPrimitive& a, const SignedPrimitive& b, double near) {
  const Primitive3D &p = a.primitive, &q = b.primitive;
  if (p.kind != q.kind || p.sides != q.sides || a.positive != b.positive) return false;
  if (norm(Vec3{p.cx - q.cx, p.cy - q.cy, p.cz - q.cz}) > near) return false;
  for (int i = 0; i < 3; ++i)
    if (std::abs(p.dims[i] - q.dims[i]) > near) return false;
  const Mat3 r = p.rotation.matrix(), s = q.rotation.matrix();
  const double reach = std::max({p.dims[0], p.dims[1], p.dims[2], 1e-12});
  for (int c = 0; c < 3; ++c)
    if (norm(sub(column(r, c), column(s, c))) * reach > 2 * near) return false;
  return true;
}

void add_distinct(std::vector<SignedPrimitive>& pool, const std::vector<SignedPrimitive>& more,
                  double diagonal) {
  for (const SignedPrimitive& p : more)
    if (std::none_of(pool.begin(), pool.end(),
                     [&](const SignedPrimitive& q) { return alike(p, q, 0.01 * diagonal); }))
      pool.push_back(p);
}

void orient_outwards(std::vector<Vec3>& normals, const std::vector<Vec3>& points,
                     const VoxelGrid& solid) {
  const double step = 1.5 * solid.voxel_size();
  for (std::size_t i = 0; i < normals.size() && i < points.size(); ++i) {
    const Vec3 ahead = add(points[i], scale(normals[i], step));
    const Vec3 behind = sub(points[i], scale(normals[i], step));
    if (solid_at(solid, ahead) && !solid_at(solid, behind)) normals[i] = scale(normals[i], -1.0);
  }
}

}  // namespace csgfit
