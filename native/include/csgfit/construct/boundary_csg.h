// Boundary to CSG (issue 42): a tree built from the surfaces of a mesh, not searched for. The
// mesh's surfaces are the halfspaces (Shapiro and Vossler), with separating ones where fillets
// and round ends need them; points labelled inside or outside by the mesh tell which cells of
// their arrangement are solid; and a cover of the solid cells by products of halfspaces (seed
// 001's dominant halfspaces, then positives less holes chosen by a weighted set cover) is the
// tree: boxes, cylinders with their caps, cones, balls, tori, as a designer would draw them.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "csgfit/features/mesh_surfaces.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

struct ConstructionOptions {
  /// Kinds the tree may use: a surface whose primitive is not among them gives no halfspace
  /// (its region is left to the search). Needs boxes (planes are written as boxes).
  PrimitiveSet3D kinds = PrimitiveSet3D::all();
  /// Polygons of up to this many sides stay polygons ($fn prisms); finer ones are written round.
  int max_polygon_sides = 16;
  std::size_t volume_samples = 120000;  ///< voxel centres labelled over the part's box (about)
  std::size_t face_samples = 60000;     ///< point pairs beside the faces (about)
  std::uint64_t seed = 1;
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// The constructed tree and how well it explains the mesh.
struct Construction {
  bool built = false;         ///< whether `tree` is a tree of the part (else it is to be ignored)
  Node3D tree;                ///< in the mesh's coordinates
  std::size_t literals = 0;   ///< halfspaces of the arrangement
  std::size_t samples = 0;
  std::size_t positives = 0, holes = 0;
  /// Share of the solid (by the samples' weight) the tree misses, and of it the tree adds.
  double missed = 0, extra = 0;
  double seconds = 0;
};

/// Builds a tree from the surfaces of a mesh (segment_mesh_surfaces). Deterministic for a
/// given seed. Gives no tree for a mesh whose faces are not surfaces (MeshSurfaces::structured
/// below one half: a scan, a noisy soup): the search is the tool there.
Construction construct_from_surfaces(const MeshSurfaces& surfaces, const ConstructionOptions& options = {});

}  // namespace csgfit
