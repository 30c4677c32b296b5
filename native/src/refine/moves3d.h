// Internal to refine/ and optimise/: the parameters of a 3D primitive that the local optimisers
// move, and how one step moves each.
#pragma once

#include <algorithm>
#include <cmath>

#include "csgfit/model/primitive3d.h"
#include "csgfit/refine/local_opt.h"
#include "refine/moves.h"

namespace csgfit {

struct Moves3D {
  // Face0Minus .. Face2Plus: one face of a box moved outwards along its local axis, the
  // others kept. Corner: a rounded box's corner radius.
  enum class Param { X, Y, Z, Dim0, Dim1, Dim2, TurnX, TurnY, TurnZ, Apex, Corner,
                     Face0Minus, Face0Plus, Face1Minus, Face1Plus, Face2Minus, Face2Plus };
  static constexpr int kMaxParams = 13;

  /// Steps are in model units; one voxel is this long.
  double unit = 1.0;
  /// A box's (and a rounded box's) faces move one at a time instead of its sizes: a face off by
  /// a little cannot get there by growing (its opposite moves too) or by shifting.
  bool box_faces = false;

  // The parameters worth moving for a primitive.
  int params_of(const Primitive3D& p, const LocalOptOptions& o, Param out[kMaxParams]) const {
    const PrimitiveKind3D kind = p.kind;
    int n = 0;
    for (Param position : {Param::X, Param::Y, Param::Z}) out[n++] = position;
    if (o.move_sizes && box_faces &&
        (kind == PrimitiveKind3D::Box || kind == PrimitiveKind3D::RoundedBox)) {
      for (int f = 0; f < 6; ++f) out[n++] = static_cast<Param>(static_cast<int>(Param::Face0Minus) + f);
    } else if (o.move_sizes) {
      int dims[3];
      const int nd = free_dims(kind, dims);
      for (int i = 0; i < nd; ++i)
        out[n++] = static_cast<Param>(static_cast<int>(Param::Dim0) + dims[i]);
    }
    if (o.move_sizes && has_free_corner(kind)) out[n++] = Param::Corner;
    if (o.move_orientation && kind != PrimitiveKind3D::Sphere) {
      out[n++] = Param::TurnX;
      out[n++] = Param::TurnY;
      // A turn about its own axis leaves a round cylinder, cone or torus as it is (a
      // polygon's is its phase).
      if (!is_axially_symmetric(p)) out[n++] = Param::TurnZ;
      if (kind == PrimitiveKind3D::TriangularPrism) out[n++] = Param::Apex;
    }
    return n;
  }

  // How far the primitive's furthest point lies from its centre.
  static double reach(const Primitive3D& p) {
    const Vec3& d = p.dims;
    switch (p.kind) {
      case PrimitiveKind3D::Box:
      case PrimitiveKind3D::RoundedBox:
      case PrimitiveKind3D::TriangularPrism:
        return 0.5 * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      case PrimitiveKind3D::Torus:
        return d[0] + d[1];
      case PrimitiveKind3D::Cylinder:
      case PrimitiveKind3D::Cone:
        return std::hypot(std::max(d[0], d[1]), 0.5 * d[2]);
      default:
        return std::max({d[0], d[1], d[2]});
    }
  }

  void move(Primitive3D& p, Param param, double step) const {
    const double voxel = unit;
    switch (param) {
      case Param::X:
      case Param::Y:
      case Param::Z:
        (param == Param::X ? p.cx : param == Param::Y ? p.cy : p.cz) += step;
        break;
      case Param::Dim0:
      case Param::Dim1:
      case Param::Dim2: {
        const int i = static_cast<int>(param) - static_cast<int>(Param::Dim0);
        // Radii move by half the step so that the surface moves by about `step` either way,
        // as full box sizes do on their two opposite faces.
        const bool radius =
            !(p.kind == PrimitiveKind3D::Box || p.kind == PrimitiveKind3D::RoundedBox ||
              p.kind == PrimitiveKind3D::TriangularPrism ||
              ((p.kind == PrimitiveKind3D::Cylinder || p.kind == PrimitiveKind3D::Cone) && i == 2));
        p.dims[i] += radius ? step / 2 : step;
        break;
      }
      case Param::TurnX:
      case Param::TurnY:
      case Param::TurnZ: {
        // About the local axis.
        const double deg = moves::turn_degrees(step, std::max(reach(p), voxel));
        const Quaternion turn = Quaternion::from_axis_angle(
            param == Param::TurnX, param == Param::TurnY, param == Param::TurnZ, deg);
        p.rotation = p.rotation * turn;
        p.rotation.normalize();
        break;
      }
      case Param::Apex:
        p.apex += step / std::max(0.5 * p.dims[0], voxel);
        break;
      case Param::Corner:
        // The arc's middle moves by (sqrt 2 - 1) of the radius's step: twice the step moves
        // the surface by about the step, as the other parameters do.
        p.corner += 2 * step;
        break;
      default:
        move_face(p, static_cast<int>(param) - static_cast<int>(Param::Face0Minus), step);
        break;
    }
  }

 private:
  // Face `f` (axis f / 2, the plus side when odd) moves outwards by `step`: the size grows by
  // it and the centre moves by half of it along the face's normal.
  static void move_face(Primitive3D& p, int f, double step) {
    const int axis = f / 2;
    const double sign = (f % 2) ? 0.5 : -0.5;
    p.dims[axis] += step;
    const Mat3 r = p.rotation.matrix();
    p.cx += sign * step * r[0][axis], p.cy += sign * step * r[1][axis], p.cz += sign * step * r[2][axis];
  }
};

}  // namespace csgfit
