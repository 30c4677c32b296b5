#include "csgfit/local_opt3d.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "csgfit/features3d.h"

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

namespace {

// Solves the n x n system a x = b in place by Gaussian elimination with partial pivoting;
// false when it is singular.
bool solve(std::vector<double>& a, std::vector<double>& b, int n) {
  for (int c = 0; c < n; ++c) {
    int piv = c;
    for (int r = c + 1; r < n; ++r)
      if (std::fabs(a[r * n + c]) > std::fabs(a[piv * n + c])) piv = r;
    if (!(std::fabs(a[piv * n + c]) > 1e-300)) return false;
    if (piv != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[piv * n + k]);
      std::swap(b[c], b[piv]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (int c = n - 1; c >= 0; --c) {
    double v = b[c];
    for (int k = c + 1; k < n; ++k) v -= a[c * n + k] * b[k];
    b[c] = v / a[c * n + c];
  }
  return true;
}

double sum_squares(const Primitive3D& p, const std::vector<const Vec3*>& pts) {
  double s = 0;
  for (const Vec3* q : pts) {
    const double d = p.signed_distance((*q)[0], (*q)[1], (*q)[2]);
    s += d * d;
  }
  return s;
}

// Levenberg-Marquardt on one primitive's parameters against its samples.
Primitive3D fit_to_points(const Primitive3D& start, const std::vector<const Vec3*>& pts, double voxel,
                          int iterations) {
  LocalOptOptions3D all;
  Param params[10];
  const int np = params_of(start.kind, all, params);
  const std::size_t m = pts.size();
  Primitive3D p = start;
  double cost = sum_squares(p, pts);
  double lambda = 1e-3;
  const double eps = 0.01 * voxel;
  std::vector<double> r(m), jac(m * static_cast<std::size_t>(np));
  for (int it = 0; it < iterations && cost > 0; ++it) {
    for (std::size_t i = 0; i < m; ++i) r[i] = p.signed_distance((*pts[i])[0], (*pts[i])[1], (*pts[i])[2]);
    for (int j = 0; j < np; ++j) {
      Primitive3D q = p;
      move(q, params[j], eps, voxel);
      q.normalize();
      for (std::size_t i = 0; i < m; ++i)
        jac[i * np + j] = (q.signed_distance((*pts[i])[0], (*pts[i])[1], (*pts[i])[2]) - r[i]) / eps;
    }
    std::vector<double> jtj(static_cast<std::size_t>(np * np), 0.0), jtr(static_cast<std::size_t>(np), 0.0);
    for (std::size_t i = 0; i < m; ++i)
      for (int a = 0; a < np; ++a) {
        const double ja = jac[i * np + a];
        if (ja == 0) continue;
        jtr[a] -= ja * r[i];
        for (int b = 0; b < np; ++b) jtj[a * np + b] += ja * jac[i * np + b];
      }
    bool stepped = false;
    for (int tries = 0; tries < 6 && !stepped; ++tries) {
      std::vector<double> a = jtj, b = jtr;
      for (int d = 0; d < np; ++d) a[d * np + d] += lambda * std::max(jtj[d * np + d], 1e-12);
      if (!solve(a, b, np)) {
        lambda *= 10;
        continue;
      }
      Primitive3D q = p;
      // Steps of at most two voxels per parameter: the linearisation holds no further.
      for (int j = 0; j < np; ++j) move(q, params[j], std::clamp(b[j], -2 * voxel, 2 * voxel), voxel);
      q.normalize();
      const double c = sum_squares(q, pts);
      if (c < cost) {
        p = q;
        stepped = cost - c > 1e-9 * cost;
        cost = c;
        lambda = std::max(lambda / 3, 1e-9);
        if (!stepped) return p;
      } else {
        lambda *= 4;
      }
    }
    if (!stepped) break;
  }
  return p;
}

// Kinds with one radius (dims[0]) that designers repeat: drills, bosses, balls.
bool is_round(PrimitiveKind3D k) {
  return k == PrimitiveKind3D::Cylinder || k == PrimitiveKind3D::Sphere;
}

}  // namespace

std::size_t refine_to_surface(TreeEvaluator3D& ev, const std::vector<Vec3>& samples,
                              const SurfaceFitOptions3D& options) {
  const double voxel = ev.target().voxel_size();
  const std::size_t n = ev.leaf_count();
  std::size_t changed = 0;
  if (n == 0 || samples.empty()) return 0;
  // The slack is one allowance for the whole refinement, not per primitive: spent a little at
  // a time by a hundred primitives it would add up to a visible loss.
  // It is measured from the best count seen so far: a search tree that a second lattice shows
  // to be far off (model 140: 804 voxels on the search's lattice, 33 617 on the staggered one)
  // must not leave the refinement a ceiling so high that it may trade back everything it gains.
  double ceiling = static_cast<double>(ev.mismatch().total()) + options.voxel_slack;
  // The judge of a refined primitive is the whole tree's surface: the squared signed distance
  // of the tree at every sample, capped at the inlier distance so that a feature the tree
  // lacks does not dominate. A primitive's own samples can pull it where it no longer makes
  // the tree's surface (a box hidden inside another takes samples of the face above it), so a
  // refinement that lowers its own residual is kept only if it lowers the tree's, or the
  // voxel mismatch.
  // Clamping commutes with min, max and negation, so the capped tree distance can change only
  // at samples within the cap of the changed primitive's old or new surface: only those are
  // re-evaluated.
  const double cap = options.inlier * voxel;
  auto capped = [&](const Vec3& s) {
    const double d = std::min(std::fabs(ev.signed_distance(s[0], s[1], s[2])), cap);
    return d * d;
  };
  std::vector<double> contribution(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) contribution[k] = capped(samples[k]);
  std::vector<std::size_t> near;
  std::vector<double> trial;
  for (int round = 0; round < options.rounds; ++round) {
    std::vector<std::vector<const Vec3*>> assigned(n);
    for (const Vec3& s : samples) {
      std::size_t best = n;
      double best_d = cap;
      for (std::size_t i = 0; i < n; ++i) {
        const double d = std::fabs(ev.leaf(i).signed_distance(s[0], s[1], s[2]));
        if (d < best_d) {
          best_d = d;
          best = i;
        }
      }
      if (best < n) assigned[best].push_back(&s);
    }
    std::size_t round_changes = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::chrono::steady_clock::now() >= options.deadline) return changed;
      Param params[10];
      const int np = params_of(ev.leaf(i).kind, LocalOptOptions3D{}, params);
      if (assigned[i].size() < static_cast<std::size_t>(3 * np)) continue;
      const Primitive3D refined = fit_to_points(ev.leaf(i), assigned[i], voxel, options.iterations);
      if (refined == ev.leaf(i)) continue;
      const Mismatch m = ev.try_leaf(i, refined);
      if (static_cast<double>(m.total()) > ceiling) continue;
      const Primitive3D old = ev.leaf(i);
      near.clear();
      for (std::size_t k = 0; k < samples.size(); ++k) {
        const Vec3& s = samples[k];
        if (std::fabs(old.signed_distance(s[0], s[1], s[2])) < cap ||
            std::fabs(refined.signed_distance(s[0], s[1], s[2])) < cap)
          near.push_back(k);
      }
      ev.leaf(i) = refined;
      trial.resize(near.size());
      double delta = 0;
      for (std::size_t j = 0; j < near.size(); ++j) {
        trial[j] = capped(samples[near[j]]);
        delta += trial[j] - contribution[near[j]];
      }
      // The capped samples cannot see a correction of more than the cap (a search tree far
      // off on the fine grid); the voxels can: either judge may approve.
      if (!(delta < 0) && m.total() >= ev.mismatch().total()) {
        ev.leaf(i) = old;
        continue;
      }
      for (std::size_t j = 0; j < near.size(); ++j) contribution[near[j]] = trial[j];
      ev.update_leaf(i);
      ceiling = std::min(ceiling, static_cast<double>(ev.mismatch().total()) + options.voxel_slack);
      ++round_changes;
    }
    changed += round_changes;
    if (round_changes == 0) break;
  }
  return changed;
}

std::size_t snap_to_design_values(TreeEvaluator3D& ev, double voxel_slack) {
  std::size_t kept = 0;
  // One allowance for all snaps together (see refine_to_surface).
  const double ceiling = static_cast<double>(ev.mismatch().total()) + voxel_slack;
  auto attempt = [&](std::size_t i, const Primitive3D& p) {
    if (p == ev.leaf(i)) return false;
    const Mismatch m = ev.try_leaf(i, p);
    if (static_cast<double>(m.total()) > ceiling) return false;
    ev.leaf(i) = p;
    ev.update_leaf(i);
    ++kept;
    return true;
  };
  const double tol = std::cos(4.0 / kRadToDeg);
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive3D& p = ev.leaf(i);
    if (p.kind == PrimitiveKind3D::Sphere || p.rotation.is_identity()) continue;
    const Mat3 r = p.rotation.matrix();
    Primitive3D snapped = p;
    if (is_axially_symmetric(p.kind)) {
      // Only the axis (local z, column 2) matters: point it along the nearest model axis.
      int axis = 0;
      for (int a = 1; a < 3; ++a)
        if (std::fabs(r[a][2]) > std::fabs(r[axis][2])) axis = a;
      if (std::fabs(r[axis][2]) < tol) continue;
      const double sign = r[axis][2] > 0 ? 1.0 : -1.0;
      // A cone's direction matters (r1 at the bottom): keep the sign.
      if (axis == 2) snapped.rotation = sign > 0 ? Quaternion{} : Quaternion::from_axis_angle(1, 0, 0, 180);
      else if (axis == 0) snapped.rotation = Quaternion::from_axis_angle(0, 1, 0, 90 * sign);
      else snapped.rotation = Quaternion::from_axis_angle(1, 0, 0, -90 * sign);
    } else {
      // Every local axis near a signed model axis: round the matrix to that permutation.
      Mat3 m{};
      bool ok = true;
      for (int c = 0; c < 3 && ok; ++c) {
        int axis = 0;
        for (int a = 1; a < 3; ++a)
          if (std::fabs(r[a][c]) > std::fabs(r[axis][c])) axis = a;
        ok = std::fabs(r[axis][c]) >= tol;
        m[axis][c] = r[axis][c] > 0 ? 1.0 : -1.0;
      }
      if (!ok) continue;
      snapped.rotation = quaternion_from_matrix(m);
    }
    snapped.normalize();
    attempt(i, snapped);
  }
  // Equal radii: each round primitive's radius joins the first earlier one within 2 %.
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive3D& p = ev.leaf(i);
    if (!is_round(p.kind)) continue;
    for (std::size_t j = 0; j < i; ++j) {
      const Primitive3D& q = ev.leaf(j);
      if (!is_round(q.kind)) continue;
      const double a = p.dims[0], b = q.dims[0];
      if (!(std::fabs(a - b) <= 0.02 * std::max(a, b)) || a == b) continue;
      Primitive3D snapped = p;
      snapped.dims[0] = b;
      if (p.kind == PrimitiveKind3D::Sphere || p.kind == PrimitiveKind3D::Cylinder) snapped.dims[1] = b;
      if (p.kind == PrimitiveKind3D::Sphere) snapped.dims[2] = b;
      if (attempt(i, snapped)) break;
    }
  }
  // Coaxial: a bore through a boss, a counterbore, a stepped shaft. A cylinder, cone or torus
  // whose axis is parallel to an earlier one's (within half a degree) and within half a voxel
  // of it moves onto that axis, keeping its place along it.
  const double parallel = std::cos(0.5 / kRadToDeg);
  const double near_axis = 0.5 * ev.target().voxel_size();
  auto axis_of = [](const Primitive3D& p) {
    const Mat3 r = p.rotation.matrix();
    return Vec3{r[0][2], r[1][2], r[2][2]};
  };
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive3D& p = ev.leaf(i);
    if (!is_axially_symmetric(p.kind)) continue;
    const Vec3 a = axis_of(p);
    for (std::size_t j = 0; j < i; ++j) {
      const Primitive3D& q = ev.leaf(j);
      if (!is_axially_symmetric(q.kind)) continue;
      const Vec3 b = axis_of(q);
      const double cos_ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      if (std::fabs(cos_ab) < parallel) continue;
      // p's centre projected onto q's axis line.
      const Vec3 d{p.cx - q.cx, p.cy - q.cy, p.cz - q.cz};
      const double along = d[0] * b[0] + d[1] * b[1] + d[2] * b[2];
      const Vec3 on{q.cx + along * b[0], q.cy + along * b[1], q.cz + along * b[2]};
      const double off = std::hypot(p.cx - on[0], p.cy - on[1], p.cz - on[2]);
      if (!(off <= near_axis) || off == 0) continue;
      Primitive3D snapped = p;
      snapped.cx = on[0], snapped.cy = on[1], snapped.cz = on[2];
      if (attempt(i, snapped)) break;
    }
  }
  return kept;
}

std::size_t snap_to_planes(TreeEvaluator3D& ev, const std::vector<AxisPlane>& planes,
                           double tolerance, double voxel_slack) {
  if (planes.empty() || !(tolerance > 0)) return 0;
  std::vector<double> offsets[3];
  for (const AxisPlane& pl : planes)
    if (pl.axis >= 0 && pl.axis < 3 && std::isfinite(pl.offset)) offsets[pl.axis].push_back(pl.offset);
  for (auto& o : offsets) std::sort(o.begin(), o.end());
  auto nearest = [&](int axis, double f) {
    const auto& o = offsets[axis];
    double best = f;
    double best_d = tolerance;
    auto it = std::lower_bound(o.begin(), o.end(), f);
    for (auto jt : {it, it == o.begin() ? it : it - 1}) {
      if (jt == o.end()) continue;
      const double d = std::fabs(*jt - f);
      if (d <= best_d) {
        best_d = d;
        best = *jt;
      }
    }
    return best;
  };
  const double ceiling = static_cast<double>(ev.mismatch().total()) + voxel_slack;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const PrimitiveKind3D kind = ev.leaf(i).kind;
    // Local axes with planar end faces: all three for a box, the axis (z) for extrusions.
    int first = 2;
    if (kind == PrimitiveKind3D::Box) first = 0;
    else if (kind != PrimitiveKind3D::Cylinder && kind != PrimitiveKind3D::Cone &&
             kind != PrimitiveKind3D::TriangularPrism)
      continue;
    for (int j = first; j < 3; ++j) {
      for (int side = -1; side <= 1; side += 2) {
        const Primitive3D& p = ev.leaf(i);
        const Mat3 r = p.rotation.matrix();
        int axis = -1;
        for (int a = 0; a < 3; ++a)
          if (std::fabs(std::fabs(r[a][j]) - 1) < 1e-9) axis = a;
        if (axis < 0) break;  // this local axis is not along a grid axis
        // The face's world offset and the opposite face's, which stays where it is.
        const double c = axis == 0 ? p.cx : axis == 1 ? p.cy : p.cz;
        const double half = 0.5 * p.dims[static_cast<std::size_t>(j)];
        const double face = c + side * half, other = c - side * half;
        const double target = nearest(axis, face);
        if (target == face) continue;
        const double size = std::fabs(target - other);
        if (!(size > 0)) continue;
        Primitive3D q = p;
        q.dims[static_cast<std::size_t>(j)] = size;
        const double centre = 0.5 * (target + other);
        (axis == 0 ? q.cx : axis == 1 ? q.cy : q.cz) = centre;
        q.normalize();
        if (q == p) continue;
        const Mismatch m = ev.try_leaf(i, q);
        if (static_cast<double>(m.total()) > ceiling) continue;
        ev.leaf(i) = q;
        ev.update_leaf(i);
        ++moved;
      }
    }
  }
  return moved;
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
