// Features of a bitmap the seeds and the search use: connected regions, area moments,
// Euclidean distance maps and their local maxima.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/bitmap.h"

namespace csgfit {

/// A connected set of pixels with its bounding box (inclusive pixel indices).
struct Region {
  Bitmap mask;  ///< canvas-sized
  int col_min = 0, row_min = 0, col_max = -1, row_max = -1;
  std::size_t area = 0;
};

/// Connected components of `mask` restricted to the box [col_min, col_max] x [row_min, row_max]
/// (inclusive; pass the whole canvas for all of it). connectivity is 4 or 8. Components come in
/// scan order, so the result is deterministic.
std::vector<Region> connected_regions(const Bitmap& mask, int connectivity, int col_min,
                                      int row_min, int col_max, int row_max);
std::vector<Region> connected_regions(const Bitmap& mask, int connectivity);

/// Area moments of a set of pixels in the solver's frame (pixel units, y up), each pixel taken
/// as a unit square (so a pixel adds 1/12 to each axis' variance).
struct Moments {
  double area = 0;
  double cx = 0, cy = 0;
  double cxx = 0, cyy = 0, cxy = 0;  ///< central second moments divided by the area
  double lambda1 = 0, lambda2 = 0;   ///< principal variances, lambda1 >= lambda2
  double angle = 0;                  ///< direction of the major principal axis, degrees
};
Moments compute_moments(const Bitmap& mask);

/// Exact squared Euclidean distance, in pixels, from every pixel to the nearest pixel where
/// `mask` is false (0 outside the mask). Pixels outside the canvas count as false when
/// `outside_is_background` is true (so a shape touching the border has small distances there).
std::vector<float> distance_map(const Bitmap& mask, bool outside_is_background = true);

/// A local maximum of a distance map: position (pixel centre, solver frame) and distance.
struct DistancePeak {
  double x = 0, y = 0;
  double distance = 0;
};
/// Local maxima (8-neighbourhood, value >= min_distance) of the distance map of `mask`, largest
/// first, at most `limit`.
std::vector<DistancePeak> distance_peaks(const Bitmap& mask, double min_distance,
                                         std::size_t limit);

/// Pixels of `mask` with at least one 4-neighbour outside it (or on the canvas edge).
std::vector<std::pair<int, int>> boundary_pixels(const Bitmap& mask);

}  // namespace csgfit
