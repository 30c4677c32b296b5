// The 3D tape: regions are blocks of x-rows; and what only 3D counts: the tree beyond the
// grid and a second, staggered lattice.
#include "csgfit/eval/evaluator3d.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "eval/evaluator_impl.h"

namespace csgfit {

template class EvaluationTape<VoxelTape>;

namespace {

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

VoxelTape::Region VoxelTape::region_of(const Primitive3D& p, const VoxelGrid& target) {
  const Bounds3 b = p.bounds();
  Region r;
  const double h = target.voxel_size();
  centre_range(b.lo[1], b.hi[1], target.origin_y(), h, target.ny(), r.j0, r.j1);
  centre_range(b.lo[2], b.hi[2], target.origin_z(), h, target.nz(), r.k0, r.k1);
  // A primitive wholly beyond the grid in x draws nothing either.
  int i0, i1;
  centre_range(b.lo[0], b.hi[0], target.origin_x(), h, target.nx(), i0, i1);
  if (i0 > i1) r = Region{};
  return r;
}

VoxelTape::Region VoxelTape::hull(const Region& a, const Region& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return Region{std::min(a.j0, b.j0), std::max(a.j1, b.j1), std::min(a.k0, b.k0),
              std::max(a.k1, b.k1)};
}

void VoxelTape::rasterize_into(const Primitive3D& p, VoxelGrid& grid) {
  csgfit::rasterize_into(p, grid);
}

VoxelGrid VoxelTape::blank_like(const VoxelGrid& g) {
  return VoxelGrid(g.nx(), g.ny(), g.nz(), g.origin_x(), g.origin_y(), g.origin_z(),
                   g.voxel_size());
}

TreeEvaluator3D::TreeEvaluator3D(const VoxelGrid& target, Node3D& tree)
    : EvaluationTape(target, tree), mismatch_(EvaluationTape::mismatch()) {
  mismatch_.outside = outside_voxels(-1, nullptr);
}

TreeEvaluator3D::TreeEvaluator3D(const VoxelGrid& target, const VoxelGrid& staggered, Node3D& tree)
    : TreeEvaluator3D(target, tree) {
  staggered_ = std::make_unique<TreeEvaluator3D>(staggered, tree);
  mismatch_ = mismatch_ + staggered_->mismatch();
}

const Mismatch& TreeEvaluator3D::update_leaf(std::size_t i) {
  Mismatch own = EvaluationTape::update_leaf(i);
  own.outside = outside_voxels(-1, nullptr);
  mismatch_ = staggered_ ? own + staggered_->update_leaf(i) : own;
  return mismatch_;
}

Mismatch TreeEvaluator3D::try_leaf(std::size_t i, const Primitive3D& p) {
  Mismatch m = EvaluationTape::try_leaf(i, p);
  Primitive3D q = p;
  q.normalize();
  m.outside = outside_voxels(leaf_slot(i), &q);
  return staggered_ ? m + staggered_->try_leaf(i, p) : m;
}

Mismatch TreeEvaluator3D::try_without_leaf(std::size_t i) {
  Mismatch m = EvaluationTape::try_without_leaf(i);
  m.outside = outside_voxels(leaf_slot(i), nullptr);
  return staggered_ ? m + staggered_->try_without_leaf(i) : m;
}

double TreeEvaluator3D::signed_distance(int slot, double x, double y, double z, int& from) const {
  const Slot& s = this->slot(slot);
  from = slot;
  if (s.primitive) return s.primitive->signed_distance(x, y, z);
  if (s.children.empty()) return std::numeric_limits<double>::infinity();
  double d = signed_distance(s.children[0], x, y, z, from);
  for (std::size_t c = 1; c < s.children.size(); ++c) {
    int child_from = -1;
    const double e = compose_distance(s.kind, d, signed_distance(s.children[c], x, y, z, child_from));
    if (e != d) from = child_from;
    d = e;
  }
  return d;
}

double TreeEvaluator3D::signed_distance(double x, double y, double z) const {
  int from = -1;
  return root() < 0 ? std::numeric_limits<double>::infinity() : signed_distance(root(), x, y, z, from);
}

std::size_t TreeEvaluator3D::surface_leaf(double x, double y, double z, double* distance) const {
  if (distance) *distance = std::numeric_limits<double>::infinity();
  if (root() < 0) return leaf_count();
  int from = -1;
  const double d = signed_distance(root(), x, y, z, from);
  if (distance) *distance = d;
  for (std::size_t i = 0; i < leaf_count(); ++i)
    if (leaf_slot(i) == from) return i;
  return leaf_count();
}

bool TreeEvaluator3D::slot_bounds(int slot, int swap, const Primitive3D* replacement,
                                  Bounds3& out) const {
  const Slot& s = this->slot(slot);
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
  if (root() < 0 || !slot_bounds(root(), swap, replacement, b)) return 0;
  const double h = target().voxel_size();
  const double glo[3] = {target().origin_x(), target().origin_y(), target().origin_z()};
  const double ghi[3] = {glo[0] + target().nx() * h, glo[1] + target().ny() * h,
                         glo[2] + target().nz() * h};
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

}  // namespace csgfit
