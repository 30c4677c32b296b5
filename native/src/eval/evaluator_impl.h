// Internal to eval/: the definitions of EvaluationTape (eval/evaluator.h), included by
// evaluator2d.cpp and evaluator3d.cpp, which instantiate it for their tape.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "csgfit/eval/evaluator.h"

namespace csgfit {

namespace tape_words {
inline std::size_t popcount(std::uint64_t w) {
  return static_cast<std::size_t>(__builtin_popcountll(w));
}
}  // namespace tape_words

template <typename Tape>
EvaluationTape<Tape>::EvaluationTape(const Grid& target, Tree& tree)
    : target_(target), scratch_leaf_(Tape::blank_like(target)) {
  root_ = build(tree, -1);
  // One scratch grid per level of the deepest path.
  scratch_path_.assign(tree.depth() + 1, Tape::blank_like(target));
  mismatch_ = measure(masks_[static_cast<std::size_t>(root_)], Tape::all_rows(target_));
  ++evaluations_;
}

template <typename Tape>
int EvaluationTape<Tape>::build(Tree& node, int parent) {
  const int self = static_cast<int>(slots_.size());
  slots_.push_back(Slot{node.kind, parent, {}, nullptr, Region{}});
  masks_.push_back(Tape::blank_like(target_));
  if (node.is_leaf()) {
    Slot& s = slots_.back();
    s.primitive = &node.primitive;
    s.rows = Tape::region_of(node.primitive, target_);
    leaf_slots_.push_back(self);
    leaf_prims_.push_back(&node.primitive);
    Tape::rasterize_into(node.primitive, mask(self));
    return self;
  }
  if (node.children.empty()) throw std::invalid_argument("an operator node has no children");
  for (Tree& c : node.children) {
    const int child = build(c, self);
    slots_[static_cast<std::size_t>(self)].children.push_back(child);
  }
  combine(self, mask(self), Tape::all_rows(target_));
  return self;
}

template <typename Tape>
void EvaluationTape<Tape>::clear(Grid& g, const Region& r) const {
  Tape::for_each_run(r, g, [&](std::size_t at, std::size_t words) {
    std::memset(g.data() + at, 0, words * sizeof(std::uint64_t));
  });
}

template <typename Tape>
void EvaluationTape<Tape>::combine(int s, Grid& out, const Region& r, int skip_child,
                                   const Grid* replacement) const {
  if (r.empty()) return;
  const Slot& sl = slot(s);
  bool first = true;
  for (const int ch : sl.children) {
    const Grid* m = (ch == skip_child) ? replacement : &masks_[static_cast<std::size_t>(ch)];
    if (!m) continue;
    Tape::for_each_run(r, out, [&](std::size_t at, std::size_t words) {
      std::uint64_t* o = out.data() + at;
      const std::uint64_t* in = m->data() + at;
      if (first) {
        std::memcpy(o, in, words * sizeof(std::uint64_t));
        return;
      }
      switch (sl.kind) {
        case NodeKind::Union:
        case NodeKind::Primitive:
          for (std::size_t w = 0; w < words; ++w) o[w] |= in[w];
          break;
        case NodeKind::Difference:
          for (std::size_t w = 0; w < words; ++w) o[w] &= ~in[w];
          break;
        case NodeKind::Intersection:
          for (std::size_t w = 0; w < words; ++w) o[w] &= in[w];
          break;
      }
    });
    first = false;
  }
  if (first) clear(out, r);
}

template <typename Tape>
Mismatch EvaluationTape<Tape>::measure(const Grid& raster, const Region& r) const {
  // One pass for both counts: this runs after every trial move.
  Mismatch m;
  if (r.empty()) return m;
  Tape::for_each_run(r, raster, [&](std::size_t at, std::size_t words) {
    const std::uint64_t* a = raster.data() + at;
    const std::uint64_t* t = target_.data() + at;
    for (std::size_t w = 0; w < words; ++w) {
      m.excess += tape_words::popcount(a[w] & ~t[w]);
      m.uncovered += tape_words::popcount(t[w] & ~a[w]);
    }
  });
  return m;
}

template <typename Tape>
Mismatch EvaluationTape<Tape>::delta(const Grid& changed_root, const Region& r) const {
  // Only rows r differ from the current root: swap their counts.
  const Mismatch before = measure(masks_[static_cast<std::size_t>(root_)], r);
  const Mismatch after = measure(changed_root, r);
  Mismatch m;
  m.excess = mismatch_.excess - before.excess + after.excess;
  m.uncovered = mismatch_.uncovered - before.uncovered + after.uncovered;
  return m;
}

template <typename Tape>
const Mismatch& EvaluationTape<Tape>::update_leaf(std::size_t i) {
  const int s = leaf_slots_[i];
  Slot& sl = slots_[static_cast<std::size_t>(s)];
  Prim& prim = *sl.primitive;
  prim.normalize();
  const Region fresh = Tape::region_of(prim, target_);
  const Region r = Tape::hull(sl.rows, fresh);
  const Mismatch before = measure(masks_[static_cast<std::size_t>(root_)], r);
  clear(mask(s), r);
  Tape::rasterize_into(prim, mask(s));
  sl.rows = fresh;
  for (int p = sl.parent; p != -1; p = slot(p).parent) combine(p, mask(p), r);
  const Mismatch after = measure(masks_[static_cast<std::size_t>(root_)], r);
  mismatch_.excess = mismatch_.excess - before.excess + after.excess;
  mismatch_.uncovered = mismatch_.uncovered - before.uncovered + after.uncovered;
  ++evaluations_;
  return mismatch_;
}

template <typename Tape>
const typename EvaluationTape<Tape>::Grid& EvaluationTape<Tape>::propagate_scratch(
    int s, const Grid* leaf_mask, const Region& r) {
  int cur = s;
  const Grid* cur_mask = leaf_mask;
  std::size_t level = 0;
  for (int p = slot(cur).parent; p != -1; cur = p, p = slot(p).parent) {
    const Slot& sl = slot(p);
    if (!cur_mask && sl.kind == NodeKind::Difference && sl.children.front() == cur) {
      cur_mask = nullptr;  // without its first operand the whole difference goes
      continue;
    }
    bool any = false;
    for (const int ch : sl.children) {
      if (ch != cur || cur_mask) {
        any = true;
        break;
      }
    }
    if (!any) {
      cur_mask = nullptr;
      continue;
    }
    Grid& out = scratch_path_[level++];
    combine(p, out, r, cur, cur_mask);
    cur_mask = &out;
  }
  if (!cur_mask) {
    clear(scratch_leaf_, r);
    return scratch_leaf_;
  }
  return *cur_mask;
}

template <typename Tape>
Mismatch EvaluationTape<Tape>::try_leaf(std::size_t i, const Prim& p) {
  Prim q = p;
  q.normalize();
  const int s = leaf_slots_[i];
  const Region r = Tape::hull(slot(s).rows, Tape::region_of(q, target_));
  // Rows outside r keep an earlier trial's bits: nothing below reads them.
  clear(scratch_leaf_, r);
  Tape::rasterize_into(q, scratch_leaf_);
  ++evaluations_;
  return delta(slot(s).parent == -1 ? scratch_leaf_ : propagate_scratch(s, &scratch_leaf_, r), r);
}

template <typename Tape>
typename EvaluationTape<Tape>::Region EvaluationTape<Tape>::removal_rows(int s) const {
  // Pointwise operators change an output only where an input changed, so the leaf's rows
  // bound the change; except where a removed operand of an intersection leaves the others,
  // which then count wherever they are.
  Region r = slot(s).rows;
  for (int cur = s, p = slot(cur).parent; p != -1; cur = p, p = slot(p).parent) {
    const Slot& sl = slot(p);
    if (sl.kind == NodeKind::Intersection && sl.children.size() > 1) return Tape::all_rows(target_);
    const bool vanishes = (sl.kind == NodeKind::Difference && sl.children.front() == cur) ||
                          sl.children.size() == 1;
    if (!vanishes) break;
  }
  return r;
}

template <typename Tape>
Mismatch EvaluationTape<Tape>::try_without_leaf(std::size_t i) {
  ++evaluations_;
  const int s = leaf_slots_[i];
  const Region r = removal_rows(s);
  return delta(propagate_scratch(s, nullptr, r), r);
}

}  // namespace csgfit
