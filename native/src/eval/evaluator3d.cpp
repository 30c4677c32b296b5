#include "csgfit/eval/evaluator3d.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace csgfit {

namespace {

VoxelGrid empty_like(const VoxelGrid& g) {
  return VoxelGrid(g.nx(), g.ny(), g.nz(), g.origin_x(), g.origin_y(), g.origin_z(),
                   g.voxel_size());
}

inline std::size_t popcount(std::uint64_t w) { return static_cast<std::size_t>(__builtin_popcountll(w)); }

// Index range of the voxel centres within [lo, hi] along one axis, widened by one voxel on each
// side so that it always contains what rasterize() sets despite rounding.
void centre_range(double lo, double hi, double origin, double size, int n, int& first, int& last) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    first = 0;
    last = -1;
    return;
  }
  const double f = std::ceil((lo - origin) / size - 0.5) - 1;
  const double l = std::floor((hi - origin) / size - 0.5) + 1;
  first = static_cast<int>(std::clamp(f, 0.0, static_cast<double>(n)));
  last = static_cast<int>(std::clamp(l, -1.0, static_cast<double>(n - 1)));
}

}  // namespace

TreeEvaluator3D::Rows TreeEvaluator3D::rows_of(const Primitive3D& p) const {
  const Bounds3 b = p.bounds();
  Rows r;
  const double h = target_.voxel_size();
  centre_range(b.lo[1], b.hi[1], target_.origin_y(), h, target_.ny(), r.j0, r.j1);
  centre_range(b.lo[2], b.hi[2], target_.origin_z(), h, target_.nz(), r.k0, r.k1);
  // A primitive wholly beyond the grid in x draws nothing either.
  int i0, i1;
  centre_range(b.lo[0], b.hi[0], target_.origin_x(), h, target_.nx(), i0, i1);
  if (i0 > i1) r = Rows{};
  return r;
}

TreeEvaluator3D::Rows TreeEvaluator3D::all_rows() const {
  return Rows{0, target_.ny() - 1, 0, target_.nz() - 1};
}

TreeEvaluator3D::Rows TreeEvaluator3D::hull(const Rows& a, const Rows& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return Rows{std::min(a.j0, b.j0), std::max(a.j1, b.j1), std::min(a.k0, b.k0),
              std::max(a.k1, b.k1)};
}

TreeEvaluator3D::TreeEvaluator3D(const VoxelGrid& target, Node3D& tree)
    : target_(target), scratch_leaf_(empty_like(target)) {
  root_ = build(tree, -1);
  // One scratch grid per level of the deepest path.
  scratch_path_.assign(tree.depth() + 1, empty_like(target));
  own_ = measure(masks_[root_], all_rows());
  own_.outside = outside_voxels(-1, nullptr);
  mismatch_ = own_;
  ++evaluations_;
}

TreeEvaluator3D::TreeEvaluator3D(const VoxelGrid& target, const VoxelGrid& staggered, Node3D& tree)
    : TreeEvaluator3D(target, tree) {
  staggered_ = std::make_unique<TreeEvaluator3D>(staggered, tree);
  mismatch_ = own_ + staggered_->mismatch();
}

int TreeEvaluator3D::build(Node3D& node, int parent) {
  const int self = static_cast<int>(slots_.size());
  slots_.push_back(Slot{node.kind, parent, {}, nullptr, Rows{}});
  masks_.push_back(empty_like(target_));
  if (node.is_leaf()) {
    slots_[self].primitive = &node.primitive;
    slots_[self].rows = rows_of(node.primitive);
    leaf_slots_.push_back(self);
    leaf_prims_.push_back(&node.primitive);
    rasterize(node.primitive, masks_[self]);
    return self;
  }
  if (node.children.empty()) throw std::invalid_argument("an operator node has no children");
  for (Node3D& c : node.children) {
    const int child = build(c, self);
    slots_[self].children.push_back(child);
  }
  combine(self, masks_[self], all_rows());
  return self;
}

double TreeEvaluator3D::signed_distance(int slot, double x, double y, double z) const {
  const Slot& s = slots_[static_cast<std::size_t>(slot)];
  if (s.primitive) return s.primitive->signed_distance(x, y, z);
  if (s.children.empty()) return std::numeric_limits<double>::infinity();
  double d = signed_distance(s.children[0], x, y, z);
  for (std::size_t c = 1; c < s.children.size(); ++c)
    d = compose_distance(s.kind, d, signed_distance(s.children[c], x, y, z));
  return d;
}

double TreeEvaluator3D::signed_distance(double x, double y, double z) const {
  return root_ < 0 ? std::numeric_limits<double>::infinity() : signed_distance(root_, x, y, z);
}

bool TreeEvaluator3D::slot_bounds(int slot, int swap, const Primitive3D* replacement,
                                  Bounds3& out) const {
  const Slot& s = slots_[slot];
  if (s.primitive) {
    if (slot == swap) {
      if (!replacement) return false;
      Primitive3D q = *replacement;
      q.normalize();
      out = q.bounds();
    } else {
      out = s.primitive->bounds();
    }
    return true;
  }
  bool any = false;
  for (std::size_t c = 0; c < s.children.size(); ++c) {
    Bounds3 b;
    if (!slot_bounds(s.children[c], swap, replacement, b)) {
      if (c == 0 && s.kind == NodeKind::Difference) return false;
      continue;
    }
    if (!any) {
      out = b;
      any = true;
    } else if (s.kind == NodeKind::Union) {
      for (int a = 0; a < 3; ++a) {
        out.lo[a] = std::min(out.lo[a], b.lo[a]);
        out.hi[a] = std::max(out.hi[a], b.hi[a]);
      }
    } else if (s.kind == NodeKind::Intersection) {
      for (int a = 0; a < 3; ++a) {
        out.lo[a] = std::max(out.lo[a], b.lo[a]);
        out.hi[a] = std::min(out.hi[a], b.hi[a]);
      }
    }
    if (s.kind == NodeKind::Difference) break;  // the subtrahends cannot enlarge it
  }
  return any;
}

std::size_t TreeEvaluator3D::outside_voxels(int swap, const Primitive3D* replacement) const {
  Bounds3 b;
  if (root_ < 0 || !slot_bounds(root_, swap, replacement, b)) return 0;
  const double h = target_.voxel_size();
  const double glo[3] = {target_.origin_x(), target_.origin_y(), target_.origin_z()};
  const double ghi[3] = {glo[0] + target_.nx() * h, glo[1] + target_.ny() * h,
                         glo[2] + target_.nz() * h};
  double whole = 1, inside = 1;
  for (int a = 0; a < 3; ++a) {
    const double e = b.hi[a] - b.lo[a];
    if (!(e > 0)) return 0;
    whole *= e / h;
    inside *= std::max(0.0, std::min(b.hi[a], ghi[a]) - std::max(b.lo[a], glo[a])) / h;
  }
  const double out = whole - inside;
  if (!(out > 0.5)) return 0;
  return static_cast<std::size_t>(std::min(out, 1e15));
}

void TreeEvaluator3D::clear_rows(VoxelGrid& g, const Rows& r) {
  if (r.empty()) return;
  const std::size_t wpr = static_cast<std::size_t>(g.words_per_row());
  const std::size_t span = (static_cast<std::size_t>(r.j1 - r.j0) + 1) * wpr;
  for (int k = r.k0; k <= r.k1; ++k) std::memset(g.row_words(r.j0, k), 0, span * sizeof(std::uint64_t));
}

void TreeEvaluator3D::combine(int slot, VoxelGrid& out, const Rows& r, int skip_child,
                              const VoxelGrid* replacement) {
  // skip_child takes `replacement` instead of its own grid, or is left out when that is null.
  // Rows of a z-slab are contiguous, so each slab is one run of words.
  if (r.empty()) return;
  const Slot& s = slots_[slot];
  const std::size_t span = (static_cast<std::size_t>(r.j1 - r.j0) + 1) * out.words_per_row();
  bool first = true;
  for (std::size_t i = 0; i < s.children.size(); ++i) {
    const int ch = s.children[i];
    const VoxelGrid* m = (ch == skip_child) ? replacement : &masks_[ch];
    if (!m) continue;
    for (int k = r.k0; k <= r.k1; ++k) {
      std::uint64_t* o = out.row_words(r.j0, k);
      const std::uint64_t* in = m->row_words(r.j0, k);
      if (first) {
        std::memcpy(o, in, span * sizeof(std::uint64_t));
        continue;
      }
      switch (s.kind) {
        case NodeKind::Union:
        case NodeKind::Primitive:
          for (std::size_t w = 0; w < span; ++w) o[w] |= in[w];
          break;
        case NodeKind::Difference:
          for (std::size_t w = 0; w < span; ++w) o[w] &= ~in[w];
          break;
        case NodeKind::Intersection:
          for (std::size_t w = 0; w < span; ++w) o[w] &= in[w];
          break;
      }
    }
    first = false;
  }
  if (first) clear_rows(out, r);
}

Mismatch TreeEvaluator3D::measure(const VoxelGrid& raster, const Rows& r) const {
  Mismatch m;
  if (r.empty()) return m;
  const std::size_t span = (static_cast<std::size_t>(r.j1 - r.j0) + 1) * raster.words_per_row();
  for (int k = r.k0; k <= r.k1; ++k) {
    const std::uint64_t* a = raster.row_words(r.j0, k);
    const std::uint64_t* t = target_.row_words(r.j0, k);
    for (std::size_t w = 0; w < span; ++w) {
      m.excess += popcount(a[w] & ~t[w]);
      m.uncovered += popcount(t[w] & ~a[w]);
    }
  }
  return m;
}

Mismatch TreeEvaluator3D::delta(const VoxelGrid& changed_root, const Rows& r) const {
  // Only rows r differ from the current root: swap their counts.
  const Mismatch before = measure(masks_[root_], r);
  const Mismatch after = measure(changed_root, r);
  Mismatch m;
  m.excess = own_.excess - before.excess + after.excess;
  m.uncovered = own_.uncovered - before.uncovered + after.uncovered;
  return m;
}

const Mismatch& TreeEvaluator3D::update_leaf(std::size_t i) {
  const int slot = leaf_slots_[i];
  Primitive3D& prim = *slots_[slot].primitive;
  prim.normalize();
  const Rows fresh = rows_of(prim);
  const Rows r = hull(slots_[slot].rows, fresh);
  const Mismatch before = measure(masks_[root_], r);
  clear_rows(masks_[slot], r);
  rasterize_into(prim, masks_[slot]);
  slots_[slot].rows = fresh;
  for (int p = slots_[slot].parent; p != -1; p = slots_[p].parent) combine(p, masks_[p], r);
  const Mismatch after = measure(masks_[root_], r);
  own_.excess = own_.excess - before.excess + after.excess;
  own_.uncovered = own_.uncovered - before.uncovered + after.uncovered;
  own_.outside = outside_voxels(-1, nullptr);
  ++evaluations_;
  mismatch_ = staggered_ ? own_ + staggered_->update_leaf(i) : own_;
  return mismatch_;
}

const VoxelGrid& TreeEvaluator3D::propagate_scratch(int slot, const VoxelGrid* mask, const Rows& r) {
  int cur = slot;
  const VoxelGrid* cur_mask = mask;
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
    VoxelGrid& out = scratch_path_[level++];
    combine(p, out, r, cur, cur_mask);
    cur_mask = &out;
  }
  if (!cur_mask) {
    clear_rows(scratch_leaf_, r);
    return scratch_leaf_;
  }
  return *cur_mask;
}

Mismatch TreeEvaluator3D::try_leaf(std::size_t i, const Primitive3D& p) {
  Primitive3D q = p;
  q.normalize();
  const int slot = leaf_slots_[i];
  const Rows r = hull(slots_[slot].rows, rows_of(q));
  clear_rows(scratch_leaf_, r);
  rasterize_into(q, scratch_leaf_);
  ++evaluations_;
  Mismatch m = delta(slots_[slot].parent == -1 ? scratch_leaf_
                                               : propagate_scratch(slot, &scratch_leaf_, r),
                     r);
  m.outside = outside_voxels(slot, &q);
  return staggered_ ? m + staggered_->try_leaf(i, p) : m;
}

Mismatch TreeEvaluator3D::try_without_leaf(std::size_t i) {
  ++evaluations_;
  const int slot = leaf_slots_[i];
  // Pointwise operators change an output only where an input changed, so the leaf's rows
  // bound the change; except where a removed operand of an intersection leaves the others,
  // which then count wherever they are.
  Rows r = slots_[slot].rows;
  for (int cur = slot, p = slots_[cur].parent; p != -1; cur = p, p = slots_[p].parent) {
    const Slot& s = slots_[p];
    if (s.kind == NodeKind::Intersection && s.children.size() > 1) {
      r = all_rows();
      break;
    }
    const bool vanishes = (s.kind == NodeKind::Difference && s.children.front() == cur) ||
                          s.children.size() == 1;
    if (!vanishes) break;
  }
  Mismatch m = delta(propagate_scratch(slot, nullptr, r), r);
  m.outside = outside_voxels(slot, nullptr);
  return staggered_ ? m + staggered_->try_without_leaf(i) : m;
}

}  // namespace csgfit
