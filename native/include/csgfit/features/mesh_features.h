// Features of a triangle mesh the 3D pipeline uses: its dominant frame, its axis-perpendicular
// planes and points spread over its surface.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/model/mesh.h"
#include "csgfit/model/quaternion.h"

namespace csgfit {

/// A planar face of the input perpendicular to a grid axis: the plane axis = offset, and the
/// area of the input's surface on it.
struct AxisPlane {
  int axis = 0;
  double offset = 0;
  double area = 0;
};

/// The rotation that takes the axes of the mesh's dominant orthogonal frame onto the model
/// axes' nearest signed permutation, i.e. frame -> mesh: the directions with the most planar
/// face area (area-weighted normals within 2 degrees of one another), the second orthogonal
/// to the first, the third their cross product. The identity when the mesh's own axes hold at
/// least 90 % as much aligned face area (an axis-aligned part stays as drawn) or when there is
/// no planar face to go by (spheres, tori).
Quaternion dominant_frame(const TriangleMesh& mesh);

/// `count` points spread over the mesh's surface in proportion to area (the same for the same
/// seed): the samples the final least-squares refinement fits to. `normals`, when given,
/// receives each point's unit triangle normal as the triangle is wound.
std::vector<Vec3> surface_samples(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed,
                                  std::vector<Vec3>* normals = nullptr);

/// The mesh's planar faces perpendicular to a model axis (normals within half a degree of it):
/// faces whose offsets lie within `merge` of one another are one plane (at their area-weighted
/// mean), kept when it carries at least `min_area`. What snap_to_planes snaps faces to.
std::vector<AxisPlane> axis_planes(const TriangleMesh& mesh, double merge, double min_area);

}  // namespace csgfit
