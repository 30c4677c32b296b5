#include "csgfit/refine/range_refine.h"

#include <algorithm>
#include <cmath>

#include "refine/moves3d.h"
#include "refine/pattern_search.h"

namespace csgfit {

namespace {

constexpr double kUnits = 64;  // graded counts: a sample wholly wrong counts 64

// Signed distances of every leaf at every sample, cached so that moving one leaf re-evaluates
// only that leaf: the tree's distance is then composed from the cache per sample.
class EvidenceEvaluator {
 public:
  EvidenceEvaluator(Node3D& tree, const RangeEvidence& evidence) : tree_(tree), evidence_(evidence) {
    collect(tree_);
    for (const Vec3& p : evidence_.surface) samples_.push_back(p);
    for (const Vec3& p : evidence_.empty) samples_.push_back(p);
    distances_.resize(leaves_.size());
    for (std::size_t i = 0; i < leaves_.size(); ++i) fill(*leaves_[i], distances_[i]);
    mismatch_ = measure(-1, nullptr);
  }

  std::size_t leaf_count() const { return leaves_.size(); }
  Primitive3D& leaf(std::size_t i) { return *leaves_[i]; }
  const Mismatch& mismatch() const { return mismatch_; }

  Mismatch try_leaf(std::size_t i, const Primitive3D& trial) {
    fill(trial, trial_);
    return measure(static_cast<int>(i), &trial_);
  }
  void update_leaf(std::size_t i) {
    fill(*leaves_[i], distances_[i]);
    mismatch_ = measure(-1, nullptr);
  }

 private:
  void collect(Node3D& n) {
    if (n.is_leaf()) leaves_.push_back(&n.primitive);
    for (Node3D& c : n.children) collect(c);
  }
  void fill(const Primitive3D& p, std::vector<double>& out) const {
    out.resize(samples_.size());
    for (std::size_t s = 0; s < samples_.size(); ++s)
      out[s] = p.signed_distance(samples_[s][0], samples_[s][1], samples_[s][2]);
  }
  double compose(const Node3D& n, std::size_t s, int& leaf, int replaced,
                 const std::vector<double>* trial) const {
    if (n.is_leaf()) {
      const int at = leaf++;
      return at == replaced ? (*trial)[s] : distances_[at][s];
    }
    double d = compose(n.children.front(), s, leaf, replaced, trial);
    for (std::size_t c = 1; c < n.children.size(); ++c)
      d = compose_distance(n.kind, d, compose(n.children[c], s, leaf, replaced, trial));
    return d;
  }
  Mismatch measure(int replaced, const std::vector<double>* trial) const {
    const double tol = evidence_.tolerance;
    double off = 0, inside = 0;
    const std::size_t n_surface = evidence_.surface.size();
    for (std::size_t s = 0; s < samples_.size(); ++s) {
      int leaf = 0;
      const double d = compose(tree_, s, leaf, replaced, trial);
      if (s < n_surface) off += std::min(1.0, std::abs(d) / tol);
      else if (d < 0) inside += std::min(1.0, -d / tol);
    }
    Mismatch m;
    m.uncovered = static_cast<std::size_t>(std::llround(kUnits * off));
    m.excess = static_cast<std::size_t>(std::llround(kUnits * inside));
    return m;
  }

  Node3D& tree_;
  const RangeEvidence& evidence_;
  std::vector<Primitive3D*> leaves_;
  std::vector<Vec3> samples_;
  std::vector<std::vector<double>> distances_;
  std::vector<double> trial_;
  Mismatch mismatch_;
};

}  // namespace

Mismatch evidence_mismatch(const Node3D& tree, const RangeEvidence& evidence) {
  Node3D copy = tree;
  return EvidenceEvaluator(copy, evidence).mismatch();
}

double evidence_k(const RangeEvidence& evidence) {
  return 0.002 * kUnits * static_cast<double>(evidence.surface.size() + evidence.empty.size());
}

std::size_t refine_to_evidence(Node3D& tree, const RangeEvidence& evidence,
                               std::chrono::steady_clock::time_point deadline,
                               const std::atomic<bool>* cancel) {
  EvidenceEvaluator ev(tree, evidence);
  // Steps from two tolerances down to a sixteenth of one: RANSAC's fit is already within one.
  LocalOptOptions options = LocalOptOptions::pattern(40, 4, 0.125);
  options.deadline = deadline;
  options.cancel = cancel;
  return pattern_search(ev, options, {}, Moves3D{0.5 * evidence.tolerance});
}

}  // namespace csgfit
