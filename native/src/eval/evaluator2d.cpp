#include "csgfit/eval/evaluator2d.h"

#include <algorithm>
#include <stdexcept>

namespace csgfit {

TreeEvaluator::TreeEvaluator(const Bitmap& target, Node& tree)
    : target_(target),
      scratch_leaf_(target.width(), target.height()) {
  root_ = build(tree, -1);
  // One scratch raster per level of the deepest path.
  scratch_path_.assign(tree.depth() + 1, Bitmap(target.width(), target.height()));
  scratch_rows_.assign(tree.depth() + 1, Rows{});
  mismatch_ = measure(masks_[root_]);
  ++evaluations_;
}

int TreeEvaluator::build(Node& node, int parent) {
  const int self = static_cast<int>(slots_.size());
  slots_.push_back(Slot{node.kind, parent, {}, nullptr});
  masks_.emplace_back(target_.width(), target_.height());
  rows_.emplace_back();
  if (node.is_leaf()) {
    slots_[self].primitive = &node.primitive;
    leaf_slots_.push_back(self);
    leaf_prims_.push_back(&node.primitive);
    rasterize(node.primitive, masks_[self]);
    row_range(node.primitive, target_.height(), rows_[self].begin, rows_[self].end);
    return self;
  }
  if (node.children.empty()) throw std::invalid_argument("an operator node has no children");
  for (Node& c : node.children) {
    const int child = build(c, self);
    slots_[self].children.push_back(child);
  }
  combine(self, masks_[self], rows_[self], -1, nullptr, Rows{});
  return self;
}

void TreeEvaluator::combine(int slot, Bitmap& out, Rows& out_rows, int skip_child,
                            const Bitmap* replacement, Rows replacement_rows) {
  const Slot& s = slots_[slot];
  bool first = true;
  for (std::size_t i = 0; i < s.children.size(); ++i) {
    const int ch = s.children[i];
    const Bitmap* m = (ch == skip_child) ? replacement : &masks_[ch];
    if (!m) continue;
    const Rows r = (ch == skip_child) ? replacement_rows : rows_[ch];
    if (first) {
      out = *m;
      out_rows = r;
      first = false;
      continue;
    }
    switch (s.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive:
        if (r.begin < r.end) {
          out.or_rows(*m, r.begin, r.end);
          if (out_rows.begin >= out_rows.end) {
            out_rows = r;
          } else {
            out_rows.begin = std::min(out_rows.begin, r.begin);
            out_rows.end = std::max(out_rows.end, r.end);
          }
        }
        break;
      case NodeKind::Difference: {
        const int b = std::max(out_rows.begin, r.begin), e = std::min(out_rows.end, r.end);
        if (b < e) out.subtract_rows(*m, b, e);
        break;
      }
      case NodeKind::Intersection:
        out &= *m;
        out_rows.begin = std::max(out_rows.begin, r.begin);
        out_rows.end = std::min(out_rows.end, r.end);
        if (out_rows.begin >= out_rows.end) out_rows = Rows{};
        break;
    }
  }
  if (first) {
    out.clear();
    out_rows = Rows{};
  }
}

Mismatch TreeEvaluator::measure(const Bitmap& raster) const {
  // One pass for both counts: this runs after every trial move.
  Mismatch m;
  const std::uint64_t* a = raster.data();
  const std::uint64_t* t = target_.data();
  for (std::size_t i = 0; i < raster.word_count(); ++i) {
    m.excess += static_cast<std::size_t>(__builtin_popcountll(a[i] & ~t[i]));
    m.uncovered += static_cast<std::size_t>(__builtin_popcountll(t[i] & ~a[i]));
  }
  return m;
}

const Mismatch& TreeEvaluator::update_leaf(std::size_t i) {
  int slot = leaf_slots_[i];
  slots_[slot].primitive->normalize();
  rasterize(*slots_[slot].primitive, masks_[slot]);
  row_range(*slots_[slot].primitive, target_.height(), rows_[slot].begin, rows_[slot].end);
  for (int p = slots_[slot].parent; p != -1; p = slots_[p].parent) combine(p, masks_[p], rows_[p], -1, nullptr, Rows{});
  mismatch_ = measure(masks_[root_]);
  ++evaluations_;
  return mismatch_;
}

const Bitmap& TreeEvaluator::propagate_scratch(int slot, const Bitmap* mask, Rows rows) {
  int cur = slot;
  const Bitmap* cur_mask = mask;
  Rows cur_rows = rows;
  std::size_t level = 0;
  for (int p = slots_[cur].parent; p != -1; cur = p, p = slots_[p].parent) {
    const Slot& s = slots_[p];
    if (!cur_mask && s.kind == NodeKind::Difference && s.children.front() == cur) {
      cur_mask = nullptr;  // without its first operand the whole difference goes
      continue;
    }
    bool any = false;
    for (int ch : s.children) {
      if (ch != cur || cur_mask) {
        any = true;
        break;
      }
    }
    if (!any) {
      cur_mask = nullptr;
      continue;
    }
    Bitmap& out = scratch_path_[level];
    Rows& out_rows = scratch_rows_[level];
    ++level;
    combine(p, out, out_rows, cur, cur_mask, cur_rows);
    cur_mask = &out;
    cur_rows = out_rows;
  }
  if (!cur_mask) {
    scratch_leaf_.clear();
    return scratch_leaf_;
  }
  return *cur_mask;
}

Mismatch TreeEvaluator::try_leaf(std::size_t i, const Primitive& p) {
  Primitive q = p;
  q.normalize();
  rasterize(q, scratch_leaf_);
  const int slot = leaf_slots_[i];
  ++evaluations_;
  if (slots_[slot].parent == -1) return measure(scratch_leaf_);
  Rows rows;
  row_range(q, target_.height(), rows.begin, rows.end);
  return measure(propagate_scratch(slot, &scratch_leaf_, rows));
}

Mismatch TreeEvaluator::try_without_leaf(std::size_t i) {
  ++evaluations_;
  return measure(propagate_scratch(leaf_slots_[i], nullptr, Rows{}));
}

}  // namespace csgfit
