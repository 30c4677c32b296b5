#include "csgfit/optimise/sample_set.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "csgfit/error.h"
#include "csgfit/model/memory_budget.h"
#include "model/random.h"

namespace csgfit::opt {

bool any(const Column& c) {
  return std::any_of(c.begin(), c.end(), [](std::uint64_t w) { return w != 0; });
}

bool any_outside(const Column& a, const Column& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] & ~b[i]) return true;
  return false;
}

bool any_common(const Column& a, const Column& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] & b[i]) return true;
  return false;
}

namespace {

template <std::size_t D>
Box<D> union_bounds(const HalfspaceList<D>& hs) {
  Box<D> box = hs.front().bounds;
  for (const auto& h : hs) box.include(h.bounds);
  for (std::size_t a = 0; a < D; ++a) {  // a margin, so that the outside is sampled too
    const double pad = 0.02 * (box.hi[a] - box.lo[a]) + 1e-9;
    box.lo[a] -= pad, box.hi[a] += pad;
  }
  return box;
}

// A jittered grid of n^D points in the box: one uniform point per cell, so that faces that
// fall on grid planes are not sampled on the face itself.
template <std::size_t D>
void add_jittered_grid(const Box<D>& box, std::size_t n, rnd::Rng& rng, std::vector<Point<D>>& out) {
  std::size_t total = 1;
  for (std::size_t a = 0; a < D; ++a) total *= n;
  for (std::size_t i = 0; i < total; ++i) {
    Point<D> p;
    std::size_t rest = i;
    for (std::size_t a = 0; a < D; ++a) {
      const double cell = (box.hi[a] - box.lo[a]) / static_cast<double>(n);
      p[a] = box.lo[a] + cell * (static_cast<double>(rest % n) + rnd::uniform(rng, 0, 1));
      rest /= n;
    }
    out.push_back(p);
  }
}

// The halfspaces that occur positively (not under an odd number of complements and cuts).
void positive_literals(const Expr& e, bool positive, std::vector<int>& out) {
  if (e.op == ExprOp::Halfspace && positive) out.push_back(e.index);
  for (std::size_t i = 0; i < e.kids.size(); ++i) {
    const bool flip = e.op == ExprOp::Complement || (e.op == ExprOp::Difference && i > 0);
    positive_literals(e.kids[i], positive != flip, out);
  }
}

template <std::size_t D>
void pad_to_word(std::vector<Point<D>>& points) {
  while (points.size() % 64 != 0) points.push_back(points.back());
}

}  // namespace

template <std::size_t D>
SampleSet<D>::SampleSet(const HalfspaceList<D>& hs, const SamplingOptions& options) {
  if (hs.empty()) throw std::logic_error("SampleSet: no halfspaces");
  if (hs.size() > kMaxHalfspaces)
    throw InputError("the tree has " + std::to_string(hs.size()) + " primitives; optimize takes at most " +
                     std::to_string(kMaxHalfspaces));
  const std::size_t finest = options.finest ? options.finest : (D == 3 ? 48 : 256);
  std::size_t local = options.local ? options.local : (D == 3 ? 8 : 24);
  // The halfspaces' own boxes get at most 2^18 points together, whatever their number.
  while (local > 2 && static_cast<double>(hs.size()) * std::pow(static_cast<double>(local), D) > 262144.0)
    --local;
  rnd::Rng rng(rnd::splitmix(options.seed));
  const Box<D> all = union_bounds(hs);
  halfspaces_ = &hs;
  domain_ = all;
  seed_ = options.seed;
  // Coarse levels first, then every halfspace's own box (small primitives), then the finest.
  for (std::size_t n = 4; n < finest; n *= 2) {
    add_jittered_grid(all, n, rng, points_);
    pad_to_word(points_);
    level_words_.push_back(points_.size() / 64);
  }
  for (const auto& h : hs) add_jittered_grid(h.bounds, local, rng, points_);
  pad_to_word(points_);
  level_words_.push_back(points_.size() / 64);
  add_jittered_grid(all, finest, rng, points_);
  pad_to_word(points_);
  level_words_.push_back(points_.size() / 64);
  check_allocation(static_cast<double>(points_.size()) / 8.0 * static_cast<double>(hs.size()),
                   "the optimiser's samples");
  columns_.assign(hs.size(), Column(word_count(), 0));
  for (std::size_t h = 0; h < hs.size(); ++h) {
    Column& col = columns_[h];
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (hs[h].bounds.contains(points_[i]) && hs[h].contains(points_[i])) col[i / 64] |= 1ULL << (i % 64);
    }
  }
}

template <std::size_t D>
Column SampleSet<D>::evaluate_range(const Expr& e, std::size_t w0, std::size_t w1) const {
  const std::size_t n = w1 - w0;
  switch (e.op) {
    case ExprOp::Halfspace: {
      const Column& c = columns_.at(static_cast<std::size_t>(e.index));
      return Column(c.begin() + static_cast<std::ptrdiff_t>(w0), c.begin() + static_cast<std::ptrdiff_t>(w1));
    }
    case ExprOp::Opaque: throw std::logic_error("SampleSet: an opaque leaf cannot be sampled");
    case ExprOp::Empty: return Column(n, 0);
    case ExprOp::Universe: return Column(n, ~0ULL);
    case ExprOp::Complement: {
      Column c = evaluate_range(e.kids[0], w0, w1);
      for (auto& w : c) w = ~w;
      return c;
    }
    default: break;
  }
  Column acc = evaluate_range(e.kids[0], w0, w1);
  for (std::size_t k = 1; k < e.kids.size(); ++k) {
    const Column c = evaluate_range(e.kids[k], w0, w1);
    for (std::size_t i = 0; i < n; ++i) {
      if (e.op == ExprOp::Union) acc[i] |= c[i];
      else if (e.op == ExprOp::Intersection) acc[i] &= c[i];
      else acc[i] &= ~c[i];
    }
  }
  return acc;
}

template <std::size_t D>
Column SampleSet<D>::evaluate(const Expr& e) const {
  return evaluate_range(e, 0, word_count());
}

template <std::size_t D>
bool SampleSet<D>::is_empty(const Expr& e) const {
  ++decisions_;
  const std::uint64_t key = structural_hash(e);
  if (auto it = empty_cache_.find(key); it != empty_cache_.end()) {
    ++cache_hits_;
    return it->second;
  }
  bool empty = true;
  std::size_t w0 = 0;
  for (std::size_t w1 : level_words_) {
    if (any(evaluate_range(e, w0, w1))) {
      empty = false;
      break;
    }
    w0 = w1;
  }
  if (empty) empty = dense_empty(e);
  empty_cache_[key] = empty;
  return empty;
}

template <std::size_t D>
Box<D> SampleSet<D>::bounds_of(const Expr& e, bool& empty) const {
  empty = false;
  switch (e.op) {
    case ExprOp::Halfspace: return (*halfspaces_)[static_cast<std::size_t>(e.index)].bounds;
    case ExprOp::Empty: empty = true; return domain_;
    case ExprOp::Difference: return bounds_of(e.kids[0], empty);
    case ExprOp::Union: {
      Box<D> box{};
      bool any_kid = false;
      for (const Expr& k : e.kids) {
        bool k_empty = false;
        const Box<D> b = bounds_of(k, k_empty);
        if (k_empty) continue;
        if (!any_kid) box = b;
        else box.include(b);
        any_kid = true;
      }
      empty = !any_kid;
      return box;
    }
    case ExprOp::Intersection: {
      Box<D> box = domain_;
      for (const Expr& k : e.kids) {
        bool k_empty = false;
        const Box<D> b = bounds_of(k, k_empty);
        if (k_empty) { empty = true; return box; }
        for (std::size_t a = 0; a < D; ++a) box.lo[a] = std::max(box.lo[a], b.lo[a]), box.hi[a] = std::min(box.hi[a], b.hi[a]);
      }
      for (std::size_t a = 0; a < D; ++a) empty = empty || box.lo[a] > box.hi[a];
      return box;
    }
    default: return domain_;  // complement, universe
  }
}

template <std::size_t D>
bool contains(const Expr& e, const HalfspaceList<D>& halfspaces, const Point<D>& p) {
  const auto in = [&](const Expr& k) { return contains(k, halfspaces, p); };
  switch (e.op) {
    case ExprOp::Halfspace: {
      const Halfspace<D>& h = halfspaces[static_cast<std::size_t>(e.index)];
      return h.bounds.contains(p) && h.contains(p);
    }
    case ExprOp::Empty: return false;
    case ExprOp::Universe: return true;
    case ExprOp::Complement: return !in(e.kids[0]);
    case ExprOp::Union: return std::any_of(e.kids.begin(), e.kids.end(), in);
    case ExprOp::Intersection: return std::all_of(e.kids.begin(), e.kids.end(), in);
    case ExprOp::Difference: return in(e.kids[0]) && std::none_of(e.kids.begin() + 1, e.kids.end(), in);
    default: throw std::logic_error("contains: an opaque leaf cannot be sampled");
  }
}

// A jittered grid over the expression's own bounds, seeded by its structure (the same answer
// for the same expression).
template <std::size_t D>
bool SampleSet<D>::dense_empty(const Expr& e) const {
  bool empty = false;
  const Box<D> box = bounds_of(e, empty);
  if (empty) return true;
  rnd::Rng rng(rnd::splitmix(seed_ ^ structural_hash(e)));
  std::vector<Point<D>> points;
  add_jittered_grid(box, D == 3 ? 24 : 100, rng, points);
  // Every inside point of e is inside one of its positive literals: their own boxes get a grid
  // each, which finds a thin part of a small primitive that e's whole box is too large for.
  std::vector<int> positive;
  positive_literals(e, true, positive);
  std::sort(positive.begin(), positive.end());
  positive.erase(std::unique(positive.begin(), positive.end()), positive.end());
  const std::size_t per = positive.size() > 64 ? (D == 3 ? 6 : 16) : (D == 3 ? 10 : 32);
  for (int h : positive) {
    Box<D> b = (*halfspaces_)[static_cast<std::size_t>(h)].bounds;
    bool overlap = true;
    for (std::size_t a = 0; a < D; ++a) {
      b.lo[a] = std::max(b.lo[a], box.lo[a]), b.hi[a] = std::min(b.hi[a], box.hi[a]);
      overlap = overlap && b.lo[a] <= b.hi[a];
    }
    if (overlap) add_jittered_grid(b, per, rng, points);
  }
  for (const Point<D>& p : points)
    if (contains(e, *halfspaces_, p)) return false;
  return true;
}

template bool contains<2>(const Expr&, const HalfspaceList<2>&, const Point<2>&);
template bool contains<3>(const Expr&, const HalfspaceList<3>&, const Point<3>&);
template class SampleSet<2>;
template class SampleSet<3>;

}  // namespace csgfit::opt
