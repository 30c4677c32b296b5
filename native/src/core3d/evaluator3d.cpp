#include "csgfit/evaluator3d.h"

#include <stdexcept>

namespace csgfit {

namespace {
VoxelGrid empty_like(const VoxelGrid& g) {
  return VoxelGrid(g.nx(), g.ny(), g.nz(), g.origin_x(), g.origin_y(), g.origin_z(),
                   g.voxel_size());
}
}  // namespace

TreeEvaluator3D::TreeEvaluator3D(const VoxelGrid& target, Node3D& tree)
    : target_(target), scratch_leaf_(empty_like(target)) {
  root_ = build(tree, -1);
  // One scratch grid per level of the deepest path.
  scratch_path_.assign(tree.depth() + 1, empty_like(target));
  mismatch_ = measure(masks_[root_]);
  ++evaluations_;
}

int TreeEvaluator3D::build(Node3D& node, int parent) {
  const int self = static_cast<int>(slots_.size());
  slots_.push_back(Slot{node.kind, parent, {}, nullptr});
  masks_.push_back(empty_like(target_));
  if (node.is_leaf()) {
    slots_[self].primitive = &node.primitive;
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
  combine(self, masks_[self]);
  return self;
}

void TreeEvaluator3D::combine(int slot, VoxelGrid& out, int skip_child,
                              const VoxelGrid* replacement) {
  // skip_child takes `replacement` instead of its own grid, or is left out when that is null.
  const Slot& s = slots_[slot];
  bool first = true;
  for (std::size_t i = 0; i < s.children.size(); ++i) {
    const int ch = s.children[i];
    const VoxelGrid* m = (ch == skip_child) ? replacement : &masks_[ch];
    if (!m) continue;
    if (first) {
      out = *m;
      first = false;
      continue;
    }
    switch (s.kind) {
      case NodeKind::Union:
      case NodeKind::Primitive: out |= *m; break;
      case NodeKind::Difference: out.subtract(*m); break;
      case NodeKind::Intersection: out &= *m; break;
    }
  }
  if (first) out.clear();
}

Mismatch TreeEvaluator3D::measure(const VoxelGrid& raster) const {
  Mismatch m;
  m.excess = count_and_not(raster, target_);
  m.uncovered = count_and_not(target_, raster);
  return m;
}

const Mismatch& TreeEvaluator3D::update_leaf(std::size_t i) {
  const int slot = leaf_slots_[i];
  slots_[slot].primitive->normalize();
  rasterize(*slots_[slot].primitive, masks_[slot]);
  for (int p = slots_[slot].parent; p != -1; p = slots_[p].parent) combine(p, masks_[p]);
  mismatch_ = measure(masks_[root_]);
  ++evaluations_;
  return mismatch_;
}

const VoxelGrid& TreeEvaluator3D::propagate_scratch(int slot, const VoxelGrid* mask) {
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
    combine(p, out, cur, cur_mask);
    cur_mask = &out;
  }
  if (!cur_mask) {
    scratch_leaf_.clear();
    return scratch_leaf_;
  }
  return *cur_mask;
}

Mismatch TreeEvaluator3D::try_leaf(std::size_t i, const Primitive3D& p) {
  Primitive3D q = p;
  q.normalize();
  rasterize(q, scratch_leaf_);
  const int slot = leaf_slots_[i];
  ++evaluations_;
  if (slots_[slot].parent == -1) return measure(scratch_leaf_);
  return measure(propagate_scratch(slot, &scratch_leaf_));
}

Mismatch TreeEvaluator3D::try_without_leaf(std::size_t i) {
  ++evaluations_;
  return measure(propagate_scratch(leaf_slots_[i], nullptr));
}

}  // namespace csgfit
