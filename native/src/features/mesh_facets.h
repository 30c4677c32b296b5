// Internal to features/: a welded mesh's coplanar regions ("facets": one flat face, or one
// strip of a tessellated curve) and the folds between neighbouring facets, which is what the
// surface segmentation reads curves from.
#pragma once

#include <vector>

#include "csgfit/model/mesh.h"
#include "csgfit/model/quaternion.h"

namespace csgfit {

/// A maximal edge-connected set of triangles within the tolerance of one plane.
struct Facet {
  Vec3 normal{0, 0, 1};       ///< area-weighted, unit, out of the solid
  double offset = 0;          ///< normal . x on the plane
  double area = 0;
  std::vector<int> triangles;
  std::vector<int> vertices;  ///< distinct, ascending
};

/// Two facets sharing edges: the turn of the normal across them.
struct Fold {
  int a = 0, b = 0;          ///< facet indices, a < b
  Vec3 direction{0, 0, 1};   ///< unit, along the shared edges (the longest one's)
  Vec3 point{0, 0, 0};       ///< a vertex of the shared edges
  double length = 0;         ///< of the shared edges
  double degrees = 0;        ///< angle between the two normals
  bool convex = true;        ///< the solid's angle across the fold is below 180 degrees
  bool straight = true;      ///< the shared edges lie on one line
};

struct FacetMesh {
  TriangleMesh mesh;                 ///< welded
  std::vector<Vec3> triangle_normals;
  std::vector<double> triangle_areas;
  std::vector<int> facet_of;         ///< per triangle; -1 for a degenerate one
  std::vector<Facet> facets;
  std::vector<Fold> folds;
  std::vector<std::vector<int>> folds_of;  ///< per facet: indices into folds
};

/// Welds the mesh and groups its triangles into facets within `tolerance` (model units) of
/// one plane, then lists the folds between them.
FacetMesh build_facets(const TriangleMesh& mesh, double tolerance);

/// The vertices of a set of facets, each once.
std::vector<int> facet_vertices(const FacetMesh& fm, const std::vector<int>& facets);

}  // namespace csgfit

namespace csgfit {

/// A run of facets folding about one axis that one circle explains: a cylinder, or exactly a
/// regular polygon prism's sides.
struct FacetArc {
  Vec3 centre{0, 0, 0};     ///< on the axis
  Vec3 axis{0, 0, 1};       ///< unit
  double radius = 0;        ///< the circle through the facets' edges (a polygon's circumradius)
  bool convex = true;       ///< the solid is inside the circle
  int sides = 0;            ///< > 0: the facets are sides of this regular polygon
  Vec3 vertex_direction{1, 0, 0};
  std::vector<int> facets;
};

/// The arcs of the facet mesh: chains of facets whose folds run along one direction, cut into
/// runs that one circle explains within `tolerance`. Each facet is in at most one arc.
/// Facets marked in `used` take no part.
std::vector<FacetArc> find_facet_arcs(const FacetMesh& fm, const std::vector<char>& used,
                                      double tolerance, double max_fold_degrees);

/// Whether facets about an axis (sorted by angle about it, all on one circle of `radius`) are
/// sides of one regular polygon: equal turns of 360 / n, each side at the polygon's apothem.
/// Returns n (0 when not), and the direction from the axis to a vertex.
int regular_polygon(const FacetMesh& fm, const std::vector<int>& facets, const Vec3& centre,
                    const Vec3& axis, double radius, bool convex, double tolerance,
                    Vec3& vertex_direction);

}  // namespace csgfit

namespace csgfit {

struct MeshSurface;

/// Surfaces of revolution among `group` (facets joined by small folds, none in an arc): the
/// facets whose normal lines meet one axis, their profile across it cut into lines (cones,
/// cylinders, rings of a plane) and circle arcs (tori, spheres). Facets it explains are marked
/// in `used`.
std::vector<MeshSurface> find_revolutions(const FacetMesh& fm, const std::vector<int>& group,
                                          double tolerance, std::vector<char>& used);

}  // namespace csgfit
