#include "csgfit/refine/range_refine.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "refine/moves3d.h"
#include "refine/pattern_search.h"

namespace csgfit {

namespace {

constexpr double kUnits = EvidenceSamples::kUnitsPerSample;
constexpr double kHiddenUnits = 4;  // a hidden sample erased: a sixteenth of one seen

// Signed distances of every leaf at every sample, cached so that moving one leaf re-evaluates
// only that leaf: the tree's distance is then composed from the cache.
class EvidenceEvaluator {
 public:
  EvidenceEvaluator(Node3D& tree, const EvidenceSamples& samples, std::vector<bool> conjectured)
      : tree_(tree), samples_(samples), conjectured_(std::move(conjectured)),
        nothing_(samples.size(), std::numeric_limits<double>::infinity()) {
    collect(tree_);
    conjectured_.resize(leaves_.size(), false);
    distances_.resize(leaves_.size());
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
      samples_.distances(*leaves_[i], distances_[i]);
      pointers_.push_back(distances_[i].data());
    }
    mismatch_ = measure();
  }

  std::size_t leaf_count() const { return leaves_.size(); }
  Primitive3D& leaf(std::size_t i) { return *leaves_[i]; }
  const Mismatch& mismatch() const { return mismatch_; }

  Mismatch try_leaf(std::size_t i, const Primitive3D& trial) {
    samples_.distances(trial, trial_);
    pointers_[i] = trial_.data();
    const Mismatch m = measure();
    pointers_[i] = distances_[i].data();
    return m;
  }
  void update_leaf(std::size_t i) {
    samples_.distances(*leaves_[i], distances_[i]);
    pointers_[i] = distances_[i].data();
    mismatch_ = measure();
  }

 private:
  void collect(Node3D& n) {
    if (n.is_leaf()) leaves_.push_back(&n.primitive);
    for (Node3D& c : n.children) collect(c);
  }
  Mismatch measure() {
    const std::size_t n = samples_.size();
    const std::vector<double>& tree = composer_.compose(tree_, pointers_, n);
    // The conjectured cuts taken out (cutting nothing) for the hidden samples' count.
    std::vector<const double*> kept = pointers_;
    for (std::size_t i = 0; i < kept.size(); ++i)
      if (conjectured_[i]) kept[i] = nothing_.data();
    return samples_.mismatch(tree.data(), hidden_composer_.compose_from(tree_, kept, n, samples_.hidden_start()).data());
  }

  Node3D& tree_;
  const EvidenceSamples& samples_;
  std::vector<bool> conjectured_;
  const std::vector<double> nothing_;  // the distances of an empty solid
  std::vector<Primitive3D*> leaves_;
  std::vector<std::vector<double>> distances_;
  std::vector<const double*> pointers_;
  std::vector<double> trial_;
  DistanceComposer composer_, hidden_composer_;
  Mismatch mismatch_;
};

}  // namespace

EvidenceSamples::EvidenceSamples(const RangeEvidence& evidence)
    : surface_(evidence.surface.size()), hidden_(evidence.surface.size() + evidence.empty.size()),
      tolerance_(evidence.tolerance) {
  points_.reserve(hidden_ + evidence.hidden.size());
  points_.insert(points_.end(), evidence.surface.begin(), evidence.surface.end());
  points_.insert(points_.end(), evidence.empty.begin(), evidence.empty.end());
  points_.insert(points_.end(), evidence.hidden.begin(), evidence.hidden.end());
}

void EvidenceSamples::distances(const Primitive3D& p, std::vector<double>& out) const {
  out.resize(points_.size());
  p.signed_distances(points_.data(), points_.size(), out.data());
}

const std::vector<double>& DistanceComposer::compose(const Node3D& tree,
                                                     const std::vector<const double*>& leaves,
                                                     std::size_t samples) {
  return compose_from(tree, leaves, samples, 0);
}

const std::vector<double>& DistanceComposer::compose_from(const Node3D& tree,
                                                          const std::vector<const double*>& leaves,
                                                          std::size_t samples, std::size_t from) {
  // Sized before composing: a buffer must not move while a level below writes another.
  levels_.resize(static_cast<std::size_t>(tree.depth()) + 2);
  for (auto& level : levels_) level.resize(samples);
  from_ = std::min(from, samples);
  std::size_t next = 0;
  const double* root = into(tree, leaves, next, 1, levels_[0]);
  if (root != levels_[0].data())
    std::copy(root + from_, root + samples, levels_[0].begin() + static_cast<std::ptrdiff_t>(from_));
  return levels_[0];
}

namespace {

// out[s] = a[s] (op) b[s] over [from, n): one loop per operation, so that each vectorises.
void compose_span(NodeKind kind, const double* a, const double* b, double* out, std::size_t from,
                  std::size_t n) {
  switch (kind) {
    case NodeKind::Difference:
      for (std::size_t s = from; s < n; ++s) out[s] = a[s] > -b[s] ? a[s] : -b[s];
      return;
    case NodeKind::Intersection:
      for (std::size_t s = from; s < n; ++s) out[s] = a[s] > b[s] ? a[s] : b[s];
      return;
    case NodeKind::Union:
    case NodeKind::Primitive: break;
  }
  for (std::size_t s = from; s < n; ++s) out[s] = a[s] < b[s] ? a[s] : b[s];
}

}  // namespace

// The node's distances: a leaf's own array (read in place, never copied), else composed into
// `out`, with level `level` holding each further child's in turn.
const double* DistanceComposer::into(const Node3D& node, const std::vector<const double*>& leaves,
                                     std::size_t& next, std::size_t level, std::vector<double>& out) {
  if (node.is_leaf()) return leaves[next++];
  const double* so_far = into(node.children.front(), leaves, next, level + 1, out);
  for (std::size_t c = 1; c < node.children.size(); ++c) {
    const double* other = into(node.children[c], leaves, next, level + 1, levels_[level]);
    compose_span(node.kind, so_far, other, out.data(), from_, out.size());
    so_far = out.data();
  }
  return so_far;
}

Mismatch EvidenceSamples::mismatch(const double* tree, const double* unconjectured) const {
  double off = 0, inside = 0, erased = 0;
  for (std::size_t s = 0; s < surface_; ++s) off += std::min(1.0, std::abs(tree[s]) / tolerance_);
  for (std::size_t s = surface_; s < hidden_; ++s)
    if (tree[s] < 0) inside += std::min(1.0, -tree[s] / tolerance_);
  for (std::size_t s = hidden_; s < points_.size(); ++s)
    if (unconjectured[s] < 0 && tree[s] > 0)
      erased += std::min(1.0, std::min(-unconjectured[s], tree[s]) / tolerance_);
  Mismatch m;
  m.uncovered = static_cast<std::size_t>(std::llround(kUnits * off + kHiddenUnits * erased));
  m.excess = static_cast<std::size_t>(std::llround(kUnits * inside));
  return m;
}

double EvidenceSamples::k() const { return 0.007 * kUnits * static_cast<double>(surface_); }

Mismatch evidence_mismatch(const Node3D& tree, const RangeEvidence& evidence,
                           const std::vector<bool>& conjectured) {
  Node3D copy = tree;
  const EvidenceSamples samples(evidence);
  return EvidenceEvaluator(copy, samples, conjectured).mismatch();
}

double evidence_k(const RangeEvidence& evidence) { return EvidenceSamples(evidence).k(); }

std::size_t refine_to_evidence(Node3D& tree, const RangeEvidence& evidence,
                               std::chrono::steady_clock::time_point deadline,
                               const std::atomic<bool>* cancel,
                               std::vector<std::size_t> leaf_indices, int sweeps,
                               const std::vector<bool>& conjectured) {
  const EvidenceSamples samples(evidence);
  EvidenceEvaluator ev(tree, samples, conjectured);
  // Steps from two tolerances down to a sixteenth of one: RANSAC's fit is already within one.
  LocalOptOptions options = LocalOptOptions::pattern(sweeps, 4, 0.125);
  options.deadline = deadline;
  options.cancel = cancel;
  // A box's faces one at a time: a face the views see a hair off moves alone, where a cut
  // trimming it would otherwise pay (object_b seen twice: a halfspace 0.007 deep).
  Moves3D moves{0.5 * evidence.tolerance};
  moves.box_faces = true;
  return pattern_search(ev, options, std::move(leaf_indices), moves);
}

}  // namespace csgfit
