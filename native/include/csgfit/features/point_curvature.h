// Seed 004's curvature type of a scanned point (Sec. 2.2 "CT"), computed once per cloud before
// the search, from how the normals of its nearest neighbours turn.
#pragma once

#include <cstdint>
#include <vector>

#include "csgfit/model/quaternion.h"

namespace csgfit {

/// The seed's curvature classes; an edge or a saddle is Other and matches nothing.
enum class CurvatureType : std::uint8_t { Flat, Convex, Concave, Other };

/// The class of a mean normal curvature k (1 / radius, positive where the surface bends away
/// from its outward normal, as on a sphere) on a part of size `size`: flat below 2 / size, and
/// Other when the neighbours disagree (`spread`, the share of neighbours bending the other way
/// strongly, over 0.25: an edge or a saddle).
CurvatureType classify_curvature(double k, double spread, double size);

/// One class per point from its k = 12 nearest neighbours: k_j = (n_j - n_i) . (p_j - p_i) /
/// |p_j - p_i|^2, averaged. `size` is the part's diagonal.
std::vector<CurvatureType> curvature_types(const std::vector<Vec3>& points,
                                           const std::vector<Vec3>& normals, double size);

}  // namespace csgfit
