#include "csgfit/seed/surface_candidates.h"

#include <algorithm>
#include <cmath>

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
  const double contact = std::max(0.02 * out.diagonal, 6 * point_spacing(points));
  RecognisedPrimitives rec = recognise_primitives(out.patches, points, out.diagonal, contact);
  keep_allowed(rec, kinds);
  out.graph = build_precedence_graph(std::move(rec.primitives), rec.adjacent, rec.patch_points);
  return out;
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
