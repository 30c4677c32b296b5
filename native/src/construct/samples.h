// Internal to construct/: points labelled inside or outside the part, where the construction
// reads which cells of its halfspaces are solid: voxel centres over the whole domain (the
// voxeliser's robust inside test), and pairs of points just inside and just outside every
// face, so that a thin wall or a small hole has samples of its own whatever the voxel size.
#pragma once

#include <cstdint>
#include <vector>

#include "csgfit/features/mesh_surfaces.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/optimise/sample_set.h"
#include "literals.h"

namespace csgfit::construct {

using opt::Column;

/// Volume samples come first, in whole words (padded with points that take part in nothing:
/// `real` is off for them), then the face samples; a count weighs the two parts apart.
struct Samples {
  std::vector<Vec3> points;
  Column inside;              ///< bit per point: the part's solid
  Column real;                ///< bit per point: not padding
  std::size_t face_word = 0;  ///< the first word of face samples
  double face_weight = 0.1;   ///< a face sample's weight; a voxel's is 1
  Bounds3 domain;             ///< the box all points lie in
  double voxel = 0;           ///< the volume samples' spacing
  int nx = 0, ny = 0, nz = 0; ///< the volume samples' lattice, x fastest from domain.lo
  std::size_t words() const { return inside.size(); }
};

/// How densely to sample.
struct SampleOptions {
  std::size_t voxels = 120000;        ///< volume samples over the part's box (about)
  std::size_t face_samples = 60000;   ///< pairs on the faces (about)
  int fewest_per_surface = 12;        ///< pairs on every surface, however small
  std::uint64_t seed = 1;
};

/// Samples of the part whose surfaces are `surfaces` (its mesh is surfaces.mesh).
Samples sample_part(const MeshSurfaces& surfaces, const SampleOptions& options);

/// Bit per sample: empty, and between solid samples along some axis of the lattice (solid on
/// both sides along x, y or z): inside a hole, slot or pocket rather than beside the part.
Column enclosed_empty(const Samples& samples);

/// What a tree gets wrong on the samples, weighted as weight_of counts.
struct Agreement {
  double missed = 0;  ///< solid samples outside the tree
  double extra = 0;   ///< empty samples inside it
};
Agreement agreement(const Node3D& tree, const Samples& samples);

/// Bit per sample: inside the literal.
Column literal_column(const Literal& literal, const Samples& samples);

/// Population count of a column, face samples weighed by face_weight.
double weight_of(const Column& c, const Samples& s);

}  // namespace csgfit::construct
