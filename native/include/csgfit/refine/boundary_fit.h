// What the least-squares refinements of 2D trees (against the contour) and 3D trees (against
// the surface) are set with.
#pragma once

#include <chrono>

namespace csgfit {

/// Settings shared by refine_to_contour and refine_to_surface.
struct BoundaryFitOptions {
  int rounds = 3;         ///< point re-assignments
  int iterations = 8;     ///< Levenberg-Marquardt steps per primitive and round
  double inlier = 1.5;    ///< points further than this (pixels, voxels) from every primitive are ignored
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

}  // namespace csgfit
