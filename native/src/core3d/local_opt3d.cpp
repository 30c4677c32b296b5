#include "csgfit/local_opt3d.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace csgfit {

namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

enum class Param { X, Y, Z, Dim0, Dim1, Dim2, TurnX, TurnY, TurnZ, Apex };

// The parameters worth moving for a kind.
int params_of(PrimitiveKind3D kind, const LocalOptOptions3D& o, Param out[10]) {
  int n = 0;
  out[n++] = Param::X;
  out[n++] = Param::Y;
  out[n++] = Param::Z;
  if (o.move_sizes) {
    int dims[3];
    const int nd = free_dims(kind, dims);
    for (int i = 0; i < nd; ++i) out[n++] = static_cast<Param>(static_cast<int>(Param::Dim0) + dims[i]);
  }
  if (o.move_rotation && kind != PrimitiveKind3D::Sphere) {
    out[n++] = Param::TurnX;
    out[n++] = Param::TurnY;
    // A turn about its own axis leaves a cylinder, cone or torus as it is.
    if (!is_axially_symmetric(kind)) out[n++] = Param::TurnZ;
    if (kind == PrimitiveKind3D::TriangularPrism) out[n++] = Param::Apex;
  }
  return n;
}

// How far the primitive's furthest point lies from its centre.
double reach(const Primitive3D& p) {
  const Vec3& d = p.dims;
  switch (p.kind) {
    case PrimitiveKind3D::Box:
    case PrimitiveKind3D::TriangularPrism:
      return 0.5 * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    case PrimitiveKind3D::Torus: return d[0] + d[1];
    case PrimitiveKind3D::Cylinder:
    case PrimitiveKind3D::Cone: return std::hypot(std::max(d[0], d[1]), 0.5 * d[2]);
    default: return std::max({d[0], d[1], d[2]});
  }
}

void move(Primitive3D& p, Param param, double step, double voxel) {
  switch (param) {
    case Param::X: p.cx += step; break;
    case Param::Y: p.cy += step; break;
    case Param::Z: p.cz += step; break;
    case Param::Dim0:
    case Param::Dim1:
    case Param::Dim2: {
      const int i = static_cast<int>(param) - static_cast<int>(Param::Dim0);
      // Radii move by half the step so that the surface moves by about `step` either way,
      // as full box sizes do on their two opposite faces.
      const bool radius = !(p.kind == PrimitiveKind3D::Box ||
                            p.kind == PrimitiveKind3D::TriangularPrism ||
                            ((p.kind == PrimitiveKind3D::Cylinder ||
                              p.kind == PrimitiveKind3D::Cone) && i == 2));
      p.dims[i] += radius ? step / 2 : step;
      break;
    }
    case Param::TurnX:
    case Param::TurnY:
    case Param::TurnZ: {
      // Turn about the local axis by the angle that moves the furthest point by about `step`,
      // at most 15 degrees.
      const double deg = std::clamp(step / std::max(reach(p), voxel) * kRadToDeg, -15.0, 15.0);
      const Quaternion turn =
          Quaternion::from_axis_angle(param == Param::TurnX, param == Param::TurnY,
                                      param == Param::TurnZ, deg);
      p.rotation = p.rotation * turn;
      p.rotation.normalize();
      break;
    }
    case Param::Apex: p.apex += step / std::max(0.5 * p.dims[0], voxel); break;
  }
}

}  // namespace

std::size_t optimize_leaves(TreeEvaluator3D& ev, const LocalOptOptions3D& options,
                            std::vector<std::size_t> leaf_indices) {
  if (leaf_indices.empty())
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) leaf_indices.push_back(i);
  const double voxel = ev.target().voxel_size();
  std::vector<double> steps(leaf_indices.size(), options.initial_step * voxel);
  const double min_step = options.min_step * voxel;
  std::size_t accepted = 0;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    bool active = false;
    for (std::size_t li = 0; li < leaf_indices.size(); ++li) {
      double& step = steps[li];
      if (step < min_step) continue;
      if (std::chrono::steady_clock::now() >= options.deadline ||
          (options.cancel && options.cancel->load(std::memory_order_relaxed)))
        return accepted;
      active = true;
      const std::size_t leaf = leaf_indices[li];
      Param params[10];
      const int np = params_of(ev.leaf(leaf).kind, options, params);
      bool improved = false;
      for (int pi = 0; pi < np; ++pi) {
        for (double dir : {1.0, -1.0}) {
          double delta = dir * step;
          bool moved = false;
          // Keep going while it pays, doubling the stride (seed 000's "small steps towards").
          for (int rep = 0; rep < 6; ++rep) {
            Primitive3D trial = ev.leaf(leaf);
            move(trial, params[pi], delta, voxel);
            const Mismatch m = ev.try_leaf(leaf, trial);
            if (m.total() >= ev.mismatch().total()) break;
            ev.leaf(leaf) = trial;
            ev.update_leaf(leaf);
            ++accepted;
            moved = improved = true;
            delta *= 2;
          }
          if (moved) break;  // no need to try the opposite direction
        }
      }
      if (!improved) step *= 0.5;
    }
    if (!active) break;
  }
  return accepted;
}

std::size_t prune(Node3D& tree, const VoxelGrid& target, double k) {
  std::size_t removed = 0;
  const std::size_t target_count = target.count();
  for (;;) {
    if (tree.primitive_count() <= 1) break;
    TreeEvaluator3D ev(target, tree);
    const std::size_t base = ev.mismatch().total();
    std::size_t best_leaf = 0;
    double best_gain = 0;
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
      const Mismatch m = ev.try_without_leaf(i);
      if (m.excess == 0 && m.uncovered == target_count) continue;  // would leave nothing
      // Removing a leaf saves k; it pays when the extra mismatch is below that.
      const double gain = k - (static_cast<double>(m.total()) - static_cast<double>(base));
      if (gain > best_gain) {
        best_gain = gain;
        best_leaf = i;
      }
    }
    if (best_gain <= 0) break;
    std::vector<Primitive3D*> ls = leaves(tree);
    const Primitive3D* victim = ls[best_leaf];
    std::function<bool(Node3D&)> erase = [&](Node3D& n) -> bool {
      for (std::size_t c = 0; c < n.children.size(); ++c) {
        Node3D& ch = n.children[c];
        if (ch.is_leaf() && &ch.primitive == victim) {
          if (n.kind == NodeKind::Difference && c == 0)
            n.children.clear();  // the difference loses its base: the whole node goes
          else
            n.children.erase(n.children.begin() + static_cast<std::ptrdiff_t>(c));
          return true;
        }
        if (!ch.is_leaf() && erase(ch)) return true;
      }
      return false;
    };
    erase(tree);
    if (!simplify(tree)) break;  // cannot happen: more than one leaf was present
    ++removed;
  }
  return removed;
}

}  // namespace csgfit
