// Triangle meshes: the soup the readers make, its topology and orientation diagnostics, and
// the repairs the voxeliser relies on. See docs/INPUTS_3D.md.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace csgfit {

/// A triangle soup with shared vertices, in the file's own coordinates (z up by convention).
/// Triangles are counter-clockwise seen from outside when the file is oriented as usual.
struct TriangleMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Topology and orientation of a mesh, for telling the user when inside/outside is guesswork.
struct MeshReport {
  std::size_t vertices = 0;             ///< after welding equal positions
  std::size_t triangles = 0;
  std::size_t edges = 0;                ///< undirected edges
  std::size_t boundary_edges = 0;       ///< edges with one triangle: holes
  std::size_t non_manifold_edges = 0;   ///< edges with three or more triangles
  std::size_t inconsistent_edges = 0;   ///< two triangles traversing the shared edge the same way
  std::size_t components = 0;           ///< edge-connected pieces
  double signed_volume = 0;             ///< divergence theorem; < 0 when the normals point inward
  double surface_area = 0;
  std::array<double, 3> bbox_min{{0, 0, 0}};
  std::array<double, 3> bbox_max{{0, 0, 0}};

  /// Every edge has exactly two triangles.
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0; }
  /// Closed and consistently oriented (a valid solid up to self-intersections).
  bool watertight() const { return closed() && inconsistent_edges == 0; }
  bool inverted() const { return signed_volume < 0; }
};

/// Edge statistics (after welding vertices at equal positions), signed volume and bounding box.
MeshReport analyze_mesh(const TriangleMesh& mesh);

/// One sentence for the user when the mesh is far from a closed, consistently oriented solid
/// (open, non-manifold, inconsistently oriented or inverted), saying what the voxelisation does
/// about it; empty when the mesh is fine.
std::string describe_mesh_problems(const MeshReport& report);

/// Merges vertices with exactly equal coordinates and drops unused ones; returns how many
/// vertices were removed.
std::size_t weld_vertices(TriangleMesh& mesh);

/// Makes the orientation of each edge-connected piece consistent across its manifold edges,
/// keeping the orientation of the larger part (by area) of each piece. Does not flip whole
/// pieces (an inward-facing cavity shell is legitimate). Returns the number of triangles flipped.
/// Vertices must be welded for edges to be found.
std::size_t repair_orientation(TriangleMesh& mesh);

/// Signed volume by the divergence theorem (positive for outward-facing triangles).
double signed_volume(const TriangleMesh& mesh);

}  // namespace csgfit
