// Minimum set cover: greedy, redundancy removal, and exact branch and bound.
#include <algorithm>
#include <stdexcept>

#include "optimise/two_level/cube_ops.h"

namespace csgfit::two_level {
namespace detail {

std::vector<std::size_t> greedy_cover(const SetCoverInstance& instance,
                                      std::vector<std::size_t> chosen) {
  std::vector<bool> covered(instance.universe, false);
  std::size_t left = instance.universe;
  for (std::size_t s : chosen)
    for (std::size_t e : instance.subsets[s]) left -= covered[e] ? 0 : 1, covered[e] = true;
  while (left > 0) {
    std::size_t best = 0, best_gain = 0;
    for (std::size_t s = 0; s < instance.subsets.size(); ++s) {
      std::size_t gain = 0;
      for (std::size_t e : instance.subsets[s]) gain += covered[e] ? 0 : 1;
      if (gain > best_gain) best = s, best_gain = gain;
    }
    if (best_gain == 0) throw std::invalid_argument("set cover: some element is in no subset");
    chosen.push_back(best);
    for (std::size_t e : instance.subsets[best]) left -= covered[e] ? 0 : 1, covered[e] = true;
  }
  return chosen;
}

void drop_redundant(const SetCoverInstance& instance, std::vector<std::size_t>& chosen) {
  std::vector<std::size_t> times(instance.universe, 0);
  for (std::size_t s : chosen)
    for (std::size_t e : instance.subsets[s]) ++times[e];
  std::vector<std::size_t> by_size = chosen;
  std::stable_sort(by_size.begin(), by_size.end(), [&](std::size_t a, std::size_t b) {
    return instance.subsets[a].size() < instance.subsets[b].size();
  });
  for (std::size_t s : by_size) {
    const auto& elements = instance.subsets[s];
    if (!std::all_of(elements.begin(), elements.end(), [&](std::size_t e) { return times[e] > 1; }))
      continue;
    for (std::size_t e : elements) --times[e];
    chosen.erase(std::find(chosen.begin(), chosen.end(), s));
  }
}

}  // namespace detail

namespace {

// Depth-first: branch on the uncovered element with the fewest open subsets; in the j-th branch
// the first j-1 of them are excluded, so no cover is visited twice.
class BranchAndBound {
 public:
  BranchAndBound(const SetCoverInstance& instance, std::size_t node_limit)
      : instance_(instance), containing_(instance.universe), times_(instance.universe, 0),
        excluded_(instance.subsets.size(), false), node_limit_(node_limit) {
    for (std::size_t s = 0; s < instance.subsets.size(); ++s)
      for (std::size_t e : instance.subsets[s]) containing_[e].push_back(s);
    best_ = detail::greedy_cover(instance);
    detail::drop_redundant(instance, best_);
  }

  SetCoverResult run() {
    search(instance_.universe);
    return {best_, nodes_ <= node_limit_};
  }

 private:
  std::size_t gain(std::size_t s) const {
    std::size_t g = 0;
    for (std::size_t e : instance_.subsets[s]) g += times_[e] == 0 ? 1 : 0;
    return g;
  }

  // No cover of `left` elements uses fewer than left / (largest open gain) more subsets.
  std::size_t lower_bound(std::size_t left) const {
    std::size_t most = 0;
    for (std::size_t s = 0; s < excluded_.size(); ++s)
      if (!excluded_[s]) most = std::max(most, gain(s));
    if (most == 0) return left + best_.size();
    return std::max((left + most - 1) / most, disjoint_elements());
  }

  // Uncovered elements no two of which share an open subset each need a subset of their own.
  std::size_t disjoint_elements() const {
    std::vector<bool> used(excluded_.size(), false);
    std::size_t count = 0;
    for (std::size_t e = 0; e < instance_.universe; ++e) {
      if (times_[e] > 0) continue;
      const std::vector<std::size_t> open = open_subsets(e);
      if (std::any_of(open.begin(), open.end(), [&](std::size_t s) { return used[s]; })) continue;
      ++count;
      for (std::size_t s : open) used[s] = true;
    }
    return count;
  }

  void take(std::size_t s, std::size_t& left, int step) {
    for (std::size_t e : instance_.subsets[s]) {
      if (step > 0) left -= times_[e]++ == 0 ? 1 : 0;
      else left += --times_[e] == 0 ? 1 : 0;
    }
  }

  std::vector<std::size_t> open_subsets(std::size_t e) const {
    std::vector<std::size_t> open;
    for (std::size_t s : containing_[e])
      if (!excluded_[s]) open.push_back(s);
    return open;
  }

  void search(std::size_t left) {
    if (++nodes_ > node_limit_) return;
    if (left == 0) {
      if (chosen_.size() < best_.size()) best_ = chosen_;
      return;
    }
    if (chosen_.size() + lower_bound(left) >= best_.size()) return;
    std::vector<std::size_t> branch;
    for (std::size_t e = 0; e < instance_.universe; ++e) {
      if (times_[e] > 0) continue;
      std::vector<std::size_t> open = open_subsets(e);
      if (open.empty()) return;
      if (branch.empty() || open.size() < branch.size()) branch = std::move(open);
    }
    std::stable_sort(branch.begin(), branch.end(),
                     [&](std::size_t a, std::size_t b) { return gain(a) > gain(b); });
    for (std::size_t s : branch) {
      chosen_.push_back(s);
      take(s, left, +1);
      search(left);
      take(s, left, -1);
      chosen_.pop_back();
      excluded_[s] = true;
    }
    for (std::size_t s : branch) excluded_[s] = false;
  }

  const SetCoverInstance& instance_;
  std::vector<std::vector<std::size_t>> containing_;
  std::vector<std::size_t> times_;
  std::vector<bool> excluded_;
  std::vector<std::size_t> chosen_, best_;
  std::size_t nodes_ = 0, node_limit_;
};

}  // namespace

SetCoverResult set_cover_exact(const SetCoverInstance& instance, std::size_t node_limit) {
  SetCoverResult result = BranchAndBound(instance, node_limit).run();
  std::sort(result.chosen.begin(), result.chosen.end());
  return result;
}

}  // namespace csgfit::two_level
