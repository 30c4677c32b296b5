// The surfaces of a mesh read off its own triangles (issue 42): coplanar triangles become
// planes, runs of facets folding about one axis become cylinders (exactly regular n-gon prisms
// where the facets say so: nut traps, polyholes, OpenSCAD's $fn), and what else curves is
// fitted as spheres, cones and tori. Unlike RANSAC on samples, nothing is lost for being
// small: a 2 mm wall or a 3 mm hole in a 150 mm part has triangles of its own.
#pragma once

#include <vector>

#include "csgfit/features/surface_detect.h"
#include "csgfit/model/mesh.h"

namespace csgfit {

/// One surface of the mesh's boundary and the triangles that lie on it.
struct MeshSurface {
  /// Kind and parameters (SurfacePatch's conventions; `points` stays empty): a plane's `axis`
  /// is its outward normal (out of the solid); `convex` says whether the solid lies inside a
  /// curved surface (a boss, a ball) or outside it (a hole, a fillet's hollow).
  SurfacePatch shape;
  /// Cylinder: > 0 when its facets are `sides` sides of a regular polygon (the mesh is then
  /// exactly that prism); 0 for a round surface. The polygon's circumradius is shape.radius.
  int sides = 0;
  /// Cylinder with sides: unit direction across the axis from the axis to a polygon vertex.
  Vec3 vertex_direction{1, 0, 0};
  std::vector<int> triangles;
  double area = 0;
  /// Extent of the triangles along the axis (cylinder, cone, torus), measured from shape.point.
  double lo = 0, hi = 0;
  /// How far about the axis the triangles go (cylinder, cone, torus), degrees: 360 for a whole
  /// hole or boss, 90 for a rounded corner, 180 for a slot's end.
  double sweep = 360;
};

struct MeshSurfaceOptions {
  /// How far a vertex may lie from its surface, relative to the mesh's diagonal: the exactness
  /// of the file's numbers (STL stores floats), not of a fit.
  double tolerance = 2e-5;
  /// Facets folding by at most this many degrees may be one smooth surface (a 12-gon folds by
  /// 30); regular polygons up to the pentagon (72 degrees) are looked for apart.
  double smooth_fold_degrees = 40;
};

/// What the segmentation found.
struct MeshSurfaces {
  /// The mesh the triangle indices refer to: the input welded and turned outwards (same
  /// triangles in the same order).
  TriangleMesh mesh;
  std::vector<MeshSurface> surfaces;
  /// Triangles of curved regions no surface explains (free-form faces, noise).
  std::vector<int> unexplained;
  double diagonal = 0;   ///< of the mesh's bounding box
  double tolerance = 0;  ///< the absolute vertex tolerance used
  /// Share of the area on surfaces of more than one triangle: near 1 for a file a CAD program
  /// or OpenSCAD wrote, low for a scan or a noisy soup, whose faces are no surfaces.
  double structured = 0;
};

/// Segments the mesh's boundary into surfaces. Deterministic. Vertices at equal positions are
/// welded first (STL repeats them); degenerate triangles belong to no surface.
MeshSurfaces segment_mesh_surfaces(const TriangleMesh& mesh, const MeshSurfaceOptions& options = {});

}  // namespace csgfit
