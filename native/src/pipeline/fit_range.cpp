// The range stages in order (seed 002's Fig. 1): merged points and normals, surface patches,
// primitive recognition, the precedence graph and its tree, and how the tree agrees with each
// view.
#include "csgfit/pipeline/fit_range.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "csgfit/error.h"
#include "csgfit/eval/range_view.h"
#include "csgfit/features/range_evidence.h"
#include "csgfit/refine/range_refine.h"
#include "csgfit/search/equal_radii.h"
#include "csgfit/search/graph_search.h"
#include "csgfit/search/hidden_extents.h"
#include "csgfit/search/hidden_trim.h"
#include "csgfit/seed/evidence_pockets.h"
#include "csgfit/seed/surface_candidates.h"
#include "fit_request.h"
#include "model/linalg.h"

namespace csgfit {

using namespace linalg;

namespace {

struct MergedPoints {
  std::vector<Vec3> points, normals;
  double diagonal = 0;
};

// Two views of one part overlap once their cameras put them in one frame; boxes that do not
// meet are two parts (or a wrong camera_to_world).
void check_overlap(const std::vector<RangeScan>& scans) {
  std::vector<Bounds3> boxes;
  for (const RangeScan& s : scans) boxes.push_back(s.points.empty() ? Bounds3{} : bounds_of(s.points));
  for (std::size_t a = 0; a < scans.size(); ++a)
    for (std::size_t b = a + 1; b < scans.size(); ++b) {
      if (scans[a].points.empty() || scans[b].points.empty()) continue;  // merge() refuses them
      const Bounds3& p = boxes[a];
      const Bounds3& q = boxes[b];
      for (int i = 0; i < 3; ++i)
        if (p.hi[i] < q.lo[i] || q.hi[i] < p.lo[i])
          throw InputError("the views '" + scans[a].source + "' and '" + scans[b].source +
                           "' do not overlap after alignment: are they of one part?");
    }
}

MergedPoints merge(const std::vector<RangeScan>& scans) {
  MergedPoints m;
  for (const RangeScan& s : scans) {
    if (s.normals.size() != s.points.size())
      throw std::invalid_argument("fit_range: every scan needs one normal per point");
    m.points.insert(m.points.end(), s.points.begin(), s.points.end());
    m.normals.insert(m.normals.end(), s.normals.begin(), s.normals.end());
  }
  // The smallest input that can show two faces of one primitive with seed 002's tolerances.
  constexpr std::size_t kMinPoints = 100;
  if (m.points.size() < kMinPoints)
    throw InputError("too few points to fit anything (" + std::to_string(m.points.size()) +
                     ", at least " + std::to_string(kMinPoints) + " needed)");
  m.diagonal = part_diagonal(m.points);
  if (!(m.diagonal > 0) || !std::isfinite(m.diagonal))
    throw InputError("the points span no volume");
  return m;
}

std::vector<int> patch_labels(const std::vector<SurfacePatch>& patches, std::size_t n) {
  std::vector<int> label(n, -1);
  for (std::size_t k = 0; k < patches.size(); ++k)
    for (int i : patches[k].points) label[i] = static_cast<int>(k);
  return label;
}

double evidence_score(const PrecedenceGraph& g, const RangeEvidence& evidence, double k) {
  std::vector<int> leaf_nodes;
  const Node3D tree = precedence_tree(g, &leaf_nodes);
  return static_cast<double>(evidence_mismatch(tree, evidence, conjectured_leaves(g, leaf_nodes)).total()) +
         k * static_cast<double>(tree.primitive_count());
}

// Greedy: drops the primitive whose removal lowers the score most, while one does; a primitive
// stays only if it explains more of what the views saw than the size weight.
void prune_by_evidence(PrecedenceGraph& g, const RangeEvidence& evidence, double k) {
  double best = evidence_score(g, evidence, k);
  while (g.nodes.size() > 1) {
    int drop = -1;
    for (std::size_t i = 0; i < g.nodes.size(); ++i) {
      const double s = evidence_score(without_node(g, static_cast<int>(i)), evidence, k);
      if (s < best) best = s, drop = static_cast<int>(i);
    }
    if (drop < 0) return;
    g = without_node(g, drop);
  }
}

// The whole tree polished against the evidence, the result written back to the graph's nodes.
void refine_graph(PrecedenceGraph& g, const RangeEvidence& evidence,
                  std::chrono::steady_clock::time_point deadline, const std::atomic<bool>* cancel) {
  std::vector<int> leaf_nodes;
  Node3D tree = precedence_tree(g, &leaf_nodes);
  if (leaf_nodes.empty()) return;
  refine_to_evidence(tree, evidence, deadline, cancel, {}, 40, conjectured_leaves(g, leaf_nodes));
  const std::vector<const Primitive3D*> refined = leaves(static_cast<const Node3D&>(tree));
  for (std::size_t i = 0; i < refined.size(); ++i) g.nodes[leaf_nodes[i]].primitive = *refined[i];
}

// RANSAC draws its shapes at random, and another draw may read right what one read wrong (a
// block's faces joined with its neighbour's): the candidates of a few readings together.
constexpr int kReadings = 3;

std::vector<SignedPrimitive> proposals_of_readings(const SurfaceReading& first,
                                                   const MergedPoints& m,
                                                   const RangeFitOptions& o,
                                                   const std::atomic<bool>* cancel) {
  std::vector<SignedPrimitive> pool = surface_proposals(first, m.points, o.primitives);
  for (int draw = 1; draw < kReadings && !(cancel && cancel->load()); ++draw) {
    const SurfaceReading r =
        read_surface(m.points, m.normals, o.detect, o.primitives, o.seed + draw, cancel);
    add_distinct(pool, surface_proposals(r, m.points, o.primitives), m.diagonal);
  }
  return pool;
}

// What `tree` leaves unexplained, read again on its own: the points further than `tolerance`
// from its surface, where a patch too small to count among all the points may stand out.
std::vector<SignedPrimitive> residual_proposals(const Node3D& tree, const MergedPoints& m,
                                                double tolerance, const RangeFitOptions& o,
                                                const std::atomic<bool>* cancel) {
  std::vector<Vec3> points, normals;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    if (std::abs(signed_distance(tree, m.points[i][0], m.points[i][1], m.points[i][2])) > tolerance)
      points.push_back(m.points[i]), normals.push_back(m.normals[i]);
  if (points.size() < 100) return {};
  // The whole part's tolerances, not the residual's (a few small pieces far apart).
  SurfaceDetectOptions detect = o.detect;
  if (detect.epsilon <= 0) detect.epsilon = 0.0025 * m.diagonal;
  if (detect.cluster_epsilon <= 0) detect.cluster_epsilon = 0.015 * m.diagonal;
  const SurfaceReading r = read_surface(points, normals, detect, o.primitives, o.seed, cancel);
  return surface_proposals(r, points, o.primitives);
}

// Each stage below runs until it converges; the clock only stops one that has not by its share
// of --time from the start, with room left for the stages after it. Shares that a typical part
// (hallway's twelve primitives: 15 s alone on the machine) never reaches make the tree one
// seed gives the same at --time 20 as at 100, and under load: at 0.2 / 0.45 / 0.6 the first
// polish and both searches were cut on most of the larger parts, each at a different point.
constexpr double kFirstPolishShare = 0.5, kSearchShare = 0.7, kResidualSearchShare = 0.8,
                 kPolishShare = 0.9;

// Seed 002's graph tested against what the views saw (steps 4 and 5 beyond the seed): pruned
// and polished, searched over the candidates, searched again with what the residual shows
// (surface the tree leaves unexplained, read again; empty space it fills, cut away), polished
// and pruned.
void improve_against_views(RangeFitResult& result, std::vector<SignedPrimitive> pool,
                           const std::vector<RangeScan>& scans, const MergedPoints& merged,
                           const RangeFitOptions& o, std::chrono::steady_clock::time_point start,
                           const std::atomic<bool>* cancel) {
  // The surface tolerance: twice RANSAC's, so that sensor noise is not a mismatch.
  const double tolerance = 0.008 * result.diagonal;
  const RangeEvidence evidence = gather_evidence(scans, tolerance, 6000);
  const double k = evidence_k(evidence);
  prune_by_evidence(result.graph, evidence, k);
  // The graph's own primitives polished first: the search then compares candidates with a
  // tree that is as good as its structure allows.
  refine_graph(result.graph, evidence, at_fraction(start, o.time_limit, kFirstPolishShare), cancel);
  GraphSearchOptions search;
  search.k = k;
  search.cancel = cancel;
  GraphSearchStats stats;
  const auto search_until = [&](double fraction) {
    search.deadline = at_fraction(start, o.time_limit, fraction);
    result.graph = search_graph(std::move(result.graph), pool, evidence, search, &stats);
    result.stats.trees += stats.trials;
  };
  search_until(kSearchShare);
  // The residual of the tree searched so far: surface it leaves unexplained, read again, and
  // empty space it fills, cut away.
  add_distinct(pool, residual_proposals(precedence_tree(result.graph), merged, tolerance, o, cancel),
               result.diagonal);
  if (o.primitives.has(PrimitiveKind3D::Box))
    add_distinct(pool, pocket_proposals(result.graph, evidence, 0.03 * result.diagonal), result.diagonal);
  search_until(kResidualSearchShare);
  result.stats.evaluations = result.stats.trees;
  // Before the polish: under a cut through its face's plane a block's face is unseen and drifts.
  result.graph = faces_from_cuts(std::move(result.graph), evidence, k);
  refine_graph(result.graph, evidence, at_fraction(start, o.time_limit, kPolishShare), cancel);
  prune_by_evidence(result.graph, evidence, k);
  // Last, after the polish: the polish would move a trim's plane to where it takes nothing.
  result.graph = trim_hidden(std::move(result.graph), pool, evidence, k, cancel);
  // Radii before the faces: a plate's underside aligns with its rods' tangent planes.
  result.graph = equal_radii(std::move(result.graph), evidence, k);
  result.graph = align_hidden_faces(std::move(result.graph), evidence);
  result.graph = holes_through(std::move(result.graph), evidence);
  result.graph = clear_skins(std::move(result.graph), evidence, k);
}

bool report(const ProgressCallback& progress, double fraction, double seconds,
            std::size_t primitives) {
  if (!progress) return true;
  FitProgress p;
  p.fraction = fraction;
  p.seconds = seconds;
  p.best_primitives = primitives;
  return progress(p);
}

}  // namespace

RangeFitResult fit_range(const std::vector<RangeScan>& scans, const RangeFitOptions& options,
                         const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  if (scans.empty()) throw std::invalid_argument("fit_range: no scan given");
  if (options.primitives.empty()) throw std::invalid_argument("no primitive type allowed");
  check_search_options(options.time_limit, options.threads, -1);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  check_overlap(scans);
  const MergedPoints merged = merge(scans);

  RangeFitResult result;
  result.diagonal = merged.diagonal;
  SurfaceReading reading = read_surface(merged.points, merged.normals, options.detect,
                                        options.primitives, options.seed, cancel);
  std::vector<SignedPrimitive> pool = proposals_of_readings(reading, merged, options, cancel);
  result.patches = std::move(reading.patches);
  result.patch_of_point = patch_labels(result.patches, merged.points.size());
  result.graph = std::move(reading.graph);
  const bool go_on = report(progress, 0.4, elapsed(), 0) && !(cancel && cancel->load());
  if (!pool.empty() && go_on)
    improve_against_views(result, std::move(pool), scans, merged, options, start, cancel);
  result.tree = precedence_tree(result.graph);
  if (result.tree.is_leaf() && result.graph.nodes.empty())
    throw InputError("no primitive surface recognised in the points");

  report(progress, 0.8, elapsed(), result.tree.primitive_count());
  double iou_sum = 0;
  int cameras = 0;
  for (const RangeScan& scan : scans) {
    if (!scan.camera || !scan.organised()) continue;
    const DepthAgreement a =
        compare_depth(scan, tree_depth_map(result.tree, *scan.camera, 1e-4 * merged.diagonal));
    result.views.push_back({scan.source, a.silhouette_iou, a.mean_depth_error});
    iou_sum += a.silhouette_iou, ++cameras;
  }
  result.stats.primitives = result.tree.primitive_count();
  result.stats.iou = cameras ? iou_sum / cameras : 0;
  result.stats.seconds = elapsed();
  const bool cancelled = !go_on || (cancel && cancel->load());
  result.stats.stop_reason = cancelled ? "cancelled" : "converged";
  report(progress, 1.0, elapsed(), result.stats.primitives);
  return result;
}

}  // namespace csgfit
