#include "csgfit/optimise/snap3d.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "csgfit/model/quaternion.h"
#include "refine/moves3d.h"

namespace csgfit {

constexpr double kRadToDeg = moves::kRadToDeg;

namespace {

// Kinds with one radius (dims[0]) that designers repeat: drills, bosses, balls.
bool is_round(PrimitiveKind3D k) {
  return k == PrimitiveKind3D::Cylinder || k == PrimitiveKind3D::Sphere;
}

// The rotation taking local z to the nearest signed model axis when the axis lies within `tol`
// (a cosine) of it: a cone's direction matters (r1 at the bottom), so the sign is kept.
std::optional<Quaternion> axis_snapped(const Mat3& r, double tol) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (std::fabs(r[a][2]) > std::fabs(r[axis][2])) axis = a;
  if (std::fabs(r[axis][2]) < tol) return std::nullopt;
  const double sign = r[axis][2] > 0 ? 1.0 : -1.0;
  if (axis == 2) return sign > 0 ? Quaternion{} : Quaternion::from_axis_angle(1, 0, 0, 180);
  if (axis == 0) return Quaternion::from_axis_angle(0, 1, 0, 90 * sign);
  return Quaternion::from_axis_angle(1, 0, 0, -90 * sign);
}

// A polygon's turn about its axis is its phase: `axis` (the snapped axis's rotation) turned
// about its z as far as p's local x is turned from axis's x, modulo the polygon's symmetry
// (360 / sides degrees) and rounded to a multiple of 15 degrees within `within` of one.
Quaternion with_phase(const Primitive3D& p, const Quaternion& axis, double within) {
  const Mat3 a = axis.matrix(), r = p.rotation.matrix();
  double x = 0, y = 0;
  for (int i = 0; i < 3; ++i) x += a[i][0] * r[i][0], y += a[i][1] * r[i][0];
  const double period = 360.0 / p.sides;
  double phase = std::atan2(y, x) * kRadToDeg;
  phase -= period * std::round(phase / period);
  const double design = 15 * std::round(phase / 15);
  if (std::fabs(phase - design) <= within) phase = design;
  return axis * Quaternion::from_axis_angle(0, 0, 1, phase);
}

}  // namespace

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
  const double tol_degrees = 4.0, tol = std::cos(tol_degrees / kRadToDeg);
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
    const Primitive3D& p = ev.leaf(i);
    if (p.kind == PrimitiveKind3D::Sphere || p.rotation.is_identity()) continue;
    const Mat3 r = p.rotation.matrix();
    Primitive3D snapped = p;
    if (is_axially_symmetric(p.kind)) {
      // The axis (local z, column 2) along the nearest model axis; only a polygon's turn about
      // it matters besides.
      const std::optional<Quaternion> axis = axis_snapped(r, tol);
      if (!axis) continue;
      snapped.rotation = p.is_polygonal() ? with_phase(p, *axis, tol_degrees) : *axis;
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
      // A polygon's circumradius is not a circle's radius, nor a polygon's of other sides.
      if (!is_round(q.kind) || q.sides != p.sides) continue;
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

// A face counts as perpendicular to a grid axis within half a degree, as axis_planes counts
// the input's faces: the surface fit leaves turns of a few thousandths of a degree that the
// design snaps may not square up (model 109: a subtracted box turned by 0.006 degree kept its
// top 0.003 below the plate's, a skin over half the part that OpenSCAD renders).
constexpr double kAlignedCos = 0.99996192306;  // cos(0.5 degree)

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
    // Local axes with planar end faces: all three for a box or a rounded box (its sides are flat
    // where they are furthest out), the axis (z) for extrusions.
    int first = 2;
    if (kind == PrimitiveKind3D::Box || kind == PrimitiveKind3D::RoundedBox) first = 0;
    else if (kind != PrimitiveKind3D::Cylinder && kind != PrimitiveKind3D::Cone &&
             kind != PrimitiveKind3D::TriangularPrism)
      continue;
    for (int j = first; j < 3; ++j) {
      for (int side = -1; side <= 1; side += 2) {
        const Primitive3D& p = ev.leaf(i);
        const Mat3 r = p.rotation.matrix();
        int axis = -1;
        for (int a = 0; a < 3; ++a)
          if (std::fabs(r[a][j]) > kAlignedCos) axis = a;
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

}  // namespace csgfit
