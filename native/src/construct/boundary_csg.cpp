#include "csgfit/construct/boundary_csg.h"

#include "cover.h"
#include "literals.h"
#include "samples.h"
#include "to_tree.h"

namespace csgfit {

namespace {

// Past this share of the solid missed or added, the construction gives no tree.
constexpr double kUselessShare = 0.5;
// Below this share of its area on surfaces of several triangles, a mesh has no faces to build
// from (each triangle its own plane) and the construction does not try.
constexpr double kLeastStructure = 0.5;

}  // namespace

Construction construct_from_surfaces(const MeshSurfaces& surfaces, const ConstructionOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Construction out;
  if (surfaces.surfaces.empty() || !options.kinds.has(PrimitiveKind3D::Box) ||
      surfaces.structured < kLeastStructure)
    return out;
  construct::SampleOptions so;
  so.voxels = options.volume_samples;
  so.face_samples = options.face_samples;
  so.seed = options.seed;
  const construct::Samples samples = construct::sample_part(surfaces, so);
  const std::vector<construct::Literal> literals =
      construct::literals_of(surfaces, samples.domain, options.max_polygon_sides, options.kinds);
  const construct::Cells cells = construct::cells_of(samples, literals);
  const construct::Cover cover = construct::cover_cells(cells, options.deadline);
  const std::optional<Node3D> tree = construct::tree_of(cover, literals, samples.domain);
  out.literals = literals.size();
  out.samples = samples.points.size();
  out.positives = cover.positives.size();
  out.holes = cover.holes.size();
  // What the tree itself gets wrong on the samples (the cover's own count would hide a tree
  // written unlike its products).
  if (tree && cover.solid_weight > 0) {
    const construct::Agreement a = construct::agreement(*tree, samples);
    out.missed = a.missed / cover.solid_weight;
    out.extra = a.extra / cover.solid_weight;
  }
  // A tree that misses most of the part is not a tree of it (the faces were not exact: a scan,
  // a noisy file): none is better than a wrong first tree for the search.
  out.built = tree.has_value() && out.missed + out.extra <= kUselessShare;
  if (out.built) out.tree = *tree;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace csgfit
