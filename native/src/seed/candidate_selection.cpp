#include "csgfit/seed/candidate_selection.h"

#include <cstddef>

#include "csgfit/model/bit_grid.h"

namespace csgfit {

namespace {

class Selection {
 public:
  Selection(const Bitmap& target, const std::vector<Primitive>& positives,
            const std::vector<Primitive>& holes, double k)
      : target_(target), k_(k), positives_(positives.size()) {
    for (const auto* list : {&positives, &holes})
      for (const Primitive& p : *list) {
        candidates_.push_back(p);
        rasters_.emplace_back(target.width(), target.height());
        rasterize(p, rasters_.back());
      }
    chosen_.assign(candidates_.size(), false);
  }

  std::size_t size() const { return candidates_.size(); }
  bool chosen(std::size_t i) const { return chosen_[i]; }
  void toggle(std::size_t i) { chosen_[i] = !chosen_[i]; }

  double score() const {
    Bitmap shape(target_.width(), target_.height()), cut(target_.width(), target_.height());
    std::size_t count = 0;
    for (std::size_t i = 0; i < size(); ++i) {
      if (!chosen_[i]) continue;
      (i < positives_ ? shape : cut) |= rasters_[i];
      ++count;
    }
    shape.subtract(cut);
    return static_cast<double>(count_xor(shape, target_)) + k_ * static_cast<double>(count);
  }

  bool any_positive() const {
    for (std::size_t i = 0; i < positives_; ++i)
      if (chosen_[i]) return true;
    return false;
  }

  Node tree() const {
    std::vector<Node> plus, minus;
    for (std::size_t i = 0; i < size(); ++i)
      if (chosen_[i]) (i < positives_ ? plus : minus).push_back(Node::leaf(candidates_[i]));
    Node base = plus.size() == 1 ? plus.front() : Node::op(NodeKind::Union, std::move(plus));
    if (minus.empty()) return base;
    minus.insert(minus.begin(), std::move(base));
    return Node::op(NodeKind::Difference, std::move(minus));
  }

 private:
  const Bitmap& target_;
  double k_;
  std::size_t positives_;
  std::vector<Primitive> candidates_;
  std::vector<Bitmap> rasters_;
  std::vector<bool> chosen_;
};

// The single toggle that lowers the score most (only additions when `add_only`); false when none.
bool best_toggle(Selection& s, double& score, bool add_only) {
  double best = score;
  std::size_t best_i = s.size();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (add_only && s.chosen(i)) continue;
    s.toggle(i);
    const double t = s.score();
    s.toggle(i);
    if (t < best) best = t, best_i = i;
  }
  if (best_i == s.size()) return false;
  s.toggle(best_i);
  score = best;
  return true;
}

}  // namespace

std::optional<Node> select_candidates(const Bitmap& target, const std::vector<Primitive>& positives,
                                      const std::vector<Primitive>& holes, double k) {
  if (positives.empty()) return std::nullopt;
  Selection s(target, positives, holes, k);
  double score = s.score();
  while (best_toggle(s, score, true)) {
  }
  // Additions alone cannot drop what a later choice made redundant.
  for (int pass = 0; pass < 64 && best_toggle(s, score, false); ++pass) {
  }
  if (!s.any_positive()) return std::nullopt;
  Node tree = s.tree();
  simplify(tree);
  return tree;
}

}  // namespace csgfit
