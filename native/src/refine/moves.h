// Internal to refine/ and optimise/: what the moves of 2D and 3D primitives share.
#pragma once

#include <algorithm>

namespace csgfit::moves {

inline constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

/// The turn, in degrees, that moves a point `reach` from the centre by about `step`, at most 15
/// degrees either way: a long primitive turns by little, a small one not round and round.
inline double turn_degrees(double step, double reach) {
  return std::clamp(step / reach * kRadToDeg, -15.0, 15.0);
}

}  // namespace csgfit::moves
