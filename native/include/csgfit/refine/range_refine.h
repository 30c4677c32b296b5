// The whole tree against what the views saw (seed 002's step 5, beyond the seed): surface
// points should lie on the tree's surface and empty points outside it. Used to drop primitives
// the evidence does not need and to polish the rest by seed 000's pattern search.
#pragma once

#include <atomic>
#include <chrono>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/features/range_evidence.h"
#include "csgfit/model/tree3d.h"

namespace csgfit {

/// The evidence as one list of samples (the surface points, the empty ones, the hidden ones)
/// and the grading evidence_mismatch gives a tree at each: for scorers that compose a tree's
/// signed distances themselves (the graph search, the pattern search's cache).
class EvidenceSamples {
 public:
  /// The mismatch's unit: a sample wholly wrong counts this much (the grading is finer).
  static constexpr double kUnitsPerSample = 64;

  explicit EvidenceSamples(const RangeEvidence& evidence);

  const std::vector<Vec3>& points() const { return points_; }
  std::size_t size() const { return points_.size(); }
  /// Samples [0, surface_count()) are surface points, then the empty ones up to
  /// hidden_start(), then the hidden ones.
  std::size_t surface_count() const { return surface_; }
  std::size_t hidden_start() const { return hidden_; }
  double tolerance() const { return tolerance_; }
  /// `p`'s signed distance at every sample.
  void distances(const Primitive3D& p, std::vector<double>& out) const;
  /// The mismatch of a tree whose signed distance at sample s is `tree[s]`, in sixty-fourths
  /// of a sample. uncovered: surface points off the surface (graded up to one tolerance), and,
  /// at a sixteenth of that weight, hidden points that the tree without its conjectured cuts
  /// (`unconjectured`, read at the hidden samples only) holds and the tree does not: a cut that
  /// no seen surface bounds must be paid for by what the views show, not by erasing what no
  /// view saw (a cut through a plate's seen top face leaves a skin that looks the same).
  /// excess: empty points inside (graded up to one tolerance deep).
  Mismatch mismatch(const double* tree, const double* unconjectured) const;
  /// What a primitive must explain to be kept, in mismatch's units: 0.7 % of the surface
  /// samples. Relative to what was seen on the surface, not to all samples: how densely the
  /// empty space is sampled (a band around each view's silhouette, a second view) must not
  /// change which primitives pay.
  double k() const;

 private:
  std::vector<Vec3> points_;
  std::size_t surface_ = 0, hidden_ = 0;
  double tolerance_ = 0;
};

/// Composes a tree's signed distance at every sample from its leaves' distances, array by
/// array (one buffer per depth), for trees scored many times with few leaves changed.
class DistanceComposer {
 public:
  /// `leaves[i]` holds leaf i's (depth-first) distance at each of `samples` samples.
  const std::vector<double>& compose(const Node3D& tree, const std::vector<const double*>& leaves,
                                     std::size_t samples);
  /// As compose, at samples [from, samples) only (the rest of the array is not set).
  const std::vector<double>& compose_from(const Node3D& tree,
                                          const std::vector<const double*>& leaves,
                                          std::size_t samples, std::size_t from);

 private:
  const double* into(const Node3D& node, const std::vector<const double*>& leaves,
                     std::size_t& next, std::size_t level, std::vector<double>& out);
  std::vector<std::vector<double>> levels_;
  std::size_t from_ = 0;
};

/// The tree's mismatch with the evidence (EvidenceSamples::mismatch); `conjectured[i]` says
/// whether leaf i (depth-first) is a conjectured cut (none when empty).
Mismatch evidence_mismatch(const Node3D& tree, const RangeEvidence& evidence,
                           const std::vector<bool>& conjectured = {});

/// The size weight for the evidence (EvidenceSamples::k).
double evidence_k(const RangeEvidence& evidence);

/// Pattern search on the parameters of the leaves `leaf_indices` (every leaf when empty; leaves
/// counted in depth-first order) against the evidence, for at most `sweeps` passes, until
/// `deadline` (or `cancel`); `conjectured` as for evidence_mismatch. Returns the accepted moves.
std::size_t refine_to_evidence(Node3D& tree, const RangeEvidence& evidence,
                               std::chrono::steady_clock::time_point deadline,
                               const std::atomic<bool>* cancel = nullptr,
                               std::vector<std::size_t> leaf_indices = {}, int sweeps = 40,
                               const std::vector<bool>& conjectured = {});

}  // namespace csgfit
