// Range images / point clouds -> 3D CSG tree (seed 002): the one place where the range stages
// are ordered for every front end: surface patches, primitive recognition, the precedence
// graph and its tree, and the refinement against the points and the viewing rays.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/features/surface_detect.h"
#include "csgfit/model/range_scan.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/search/stats.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// Everything a range fit takes besides the scans.
struct RangeFitOptions {
  double time_limit = 20;      ///< seconds of wall time for the whole fit
  std::uint64_t seed = 1;      ///< RANSAC and refinement draws
  int threads = 0;             ///< 0 = all cores
  PrimitiveSet3D primitives = PrimitiveSet3D::parse("box,sphere,cylinder,cone,torus");
  SurfaceDetectOptions detect; ///< RANSAC tolerances (0 = relative to the part's size)
};

/// How the result agrees with each view, re-seen through the view's own camera.
struct ViewAgreement {
  std::string source;
  double silhouette_iou = 0;   ///< returns of the view vs pixels whose ray hits the tree
  double depth_error = 0;      ///< mean |depth - tree depth| over pixels both see, model units
};

struct RangeFitResult {
  Node3D tree;                          ///< in model coordinates
  PrecedenceGraph graph;                ///< nodes, arcs, subobjects, orders
  std::vector<SurfacePatch> patches;    ///< the segmentation (indices into the merged points)
  std::vector<int> patch_of_point;      ///< -1 = unassigned, per merged point
  std::vector<ViewAgreement> views;     ///< one per scan with a camera
  FitStats stats;                       ///< primitives, elapsed, stop reason; iou = silhouette
  double diagonal = 0;                  ///< of the points' bounding box
};

/// Fits a CSG tree to one or several scans of one part. Throws InputError when the scans hold
/// too few points to fit anything or when several views do not overlap (different parts), and
/// std::invalid_argument for bad options. Honours `cancel` and the progress callback (best tree
/// so far on cancel).
RangeFitResult fit_range(const std::vector<RangeScan>& scans, const RangeFitOptions& options,
                         const ProgressCallback& progress = nullptr,
                         const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
