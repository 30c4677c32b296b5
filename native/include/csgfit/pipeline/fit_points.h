// Scanned point clouds -> CSG tree with NURBS terminals (seed 004): the one place where the
// point-cloud stages are ordered: the cloud checked and read as a fitness target (normals,
// curvature types, floor samples), a NURBS patch fitted where the cloud is a height field, first
// trees from the range detector, then seed 004's GP/ES on islands (or, to compare, the voxel
// hill climbing on the same points and budget).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "csgfit/model/range_scan.h"
#include "csgfit/search/gp_search.h"

namespace csgfit {

enum class PointSearch { Gp, Hill };

struct PointsFitOptions {
  double time_limit = 30;
  std::uint64_t seed = 1;
  int threads = 0;
  /// Analytic kinds the search may use; Nurbs in the set allows the NURBS terminal.
  PrimitiveSet3D primitives = PrimitiveSet3D::parse("box,sphere,cylinder,nurbs");
  std::optional<ScanKind> scan;    ///< unset: from the normals (no point faces down = top)
  double floor = 0;                ///< top scans: the table's height
  PointSearch search = PointSearch::Gp;
  std::size_t islands = 4;
  std::size_t max_generations = 1000000;  ///< tests stop on it for a reproducible tree
};

struct PointsFitResult {
  Node3D tree;
  ScanKind scan = ScanKind::All;
  FitnessTerms terms;       ///< seed 004's fitness of the tree on every point
  FitStats stats;           ///< primitives, evaluations, seconds, stop reason
  std::size_t generations = 0, islands = 0, points = 0;
  double diagonal = 0;
  double patch_rms = -1;    ///< the NURBS patch's least-squares RMS residual, -1 without one
  std::string first_tree;   ///< where the search started: "detected", "random"
};

/// Fits a tree to the scans' points (model coordinates, normals out of the part). Throws
/// InputError for fewer than 20 points, points that are not finite, normals of zero length,
/// points on a line, or on a plane for a scan all around; std::invalid_argument for bad options.
PointsFitResult fit_points(const std::vector<RangeScan>& scans, const PointsFitOptions& options,
                           const ProgressCallback& progress = nullptr,
                           const std::atomic<bool>* cancel = nullptr);

/// Seed 004's terms of the result, as `csgfit points --report` prints them (three lines).
std::string fitness_report(const PointsFitResult& result);

}  // namespace csgfit
