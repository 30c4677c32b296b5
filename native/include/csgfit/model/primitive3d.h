// 3D primitives: box, sphere, cylinder, cone (frustum), ellipsoid, torus, triangular prism,
// seed 004's NURBS terminal and the rounded box; their scan conversion at voxel centres, volumes
// and signed distances.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "csgfit/model/bspline_surface.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/model/voxel_grid.h"

namespace csgfit {

// RoundedBox comes last so that the older kinds keep their values (and the searches that
// enumerate kinds in this order draw what they drew before it existed).
enum class PrimitiveKind3D {
  Box, Sphere, Cylinder, Cone, Ellipsoid, Torus, TriangularPrism, Nurbs, RoundedBox
};

/// Canonical lower-case name ("box", "sphere", "cylinder", "cone", "ellipsoid", "torus",
/// "prism", "nurbs", "rounded_box").
std::string_view to_string(PrimitiveKind3D kind);
/// Parses a name as written by to_string (also "cube", "frustum", "wedge", "triangular_prism",
/// "bspline", "rounded-box", "roundedbox"); throws std::invalid_argument naming the bad name.
PrimitiveKind3D primitive_kind3d_from_string(std::string_view name);


/// Axis-aligned bounds in model coordinates.
struct Bounds3 {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
};

/// The smallest box holding both boxes.
Bounds3 merged(const Bounds3& a, const Bounds3& b);
/// The smallest box holding the points (which must not be empty).
Bounds3 bounds_of(const std::vector<Vec3>& points);
/// The part [t0, t1] of the ray o + t d, t >= 0, inside the box (slab test); false when the
/// ray misses it.
bool clip_ray(const Bounds3& box, const Vec3& o, const Vec3& d, double& t0, double& t1);

/// One primitive in model coordinates (the mesh's own units, z up): a centre, a rotation and
/// dimensions in its local frame, where the shape is centred on the origin:
///  - Box:       dims = {size x, size y, size z} (full edge lengths).
///  - Sphere:    dims = {r, r, r} (kept equal; the rotation is kept at identity).
///  - Cylinder:  dims = {r, r, height}; axis local z, z in [-h/2, h/2] (dims[1] kept = dims[0]).
///  - Cone:      dims = {r1, r2, height}: a frustum with radius r1 at z = -h/2 (bottom) and r2
///               at z = +h/2 (top), axis local z; r1 or r2 may be 0 (a full cone).
///  - Cylinder and Cone with `sides` >= 3: the cross-section is the regular `sides`-gon inscribed
///               in the circle of that radius (r is the circumradius), vertex 0 on local +x and
///               vertex i at 360 i / sides degrees counter-clockwise about local z: OpenSCAD's
///               cylinder(h, r1, r2, $fn = sides) in the local frame. A Cone is then the frustum
///               of a regular pyramid, both end polygons with their vertices at the same angles.
///               The turn about local z is the polygon's phase and matters.
///  - Ellipsoid: dims = {rx, ry, rz}, semi-axes along local x, y, z.
///  - Torus:     dims = {R, r, 0}: the tube of radius r around the circle of radius R in the
///               local xy plane (axis local z), r <= R so that OpenSCAD can revolve it.
///  - TriangularPrism: dims = {w, h, depth}: seed 003's triangular block, the 2D Triangle of
///               primitive.h (base (-w/2, -h/2)-(w/2, -h/2), apex (apex * w/2, h/2)) in local
///               xy, extruded over z in [-depth/2, depth/2].
///  - Nurbs:     seed 004's NURBS terminal: `patch` is a height field z = S(x, y) over the local
///               rectangle |x| <= sx/2, |y| <= sy/2, and the solid is 0 <= z <= S(x, y) there
///               (the local plane z = 0 is its floor, the patch its top face); dims = {sx, sy,
///               top}, top the highest control height (the convex hull bounds S by it).
///               Signed distances are the vertical gap scaled by the slope (first order).
///  - RoundedBox: dims = {sx, sy, sz} as a Box's, its four edges along local z rounded with
///               radius `corner` (0 < corner <= min(sx, sy) / 2; at the bound the section is a
///               stadium, or a circle when sx = sy): the rounded rectangle, i.e. the rectangle
///               of (sx - 2 corner) x (sy - 2 corner) grown by `corner`, extruded over
///               z in [-sz/2, sz/2]. OpenSCAD's linear_extrude() offset(r = corner) square().
struct Primitive3D {
  PrimitiveKind3D kind = PrimitiveKind3D::Box;
  double cx = 0, cy = 0, cz = 0;
  Quaternion rotation;
  Vec3 dims{1, 1, 1};
  double apex = 0;  ///< TriangularPrism only
  /// RoundedBox only: the radius of its four edges along local z; normalize() keeps it in
  /// (0, min(sx, sy) / 2] and sets 0 for other kinds.
  double corner = 0;
  /// Cylinder and Cone only: 0 for the round solid, else the number of sides of the regular
  /// polygon that is its cross-section (3 .. kMaxSides); normalize() sets 0 for other kinds.
  int sides = 0;
  static constexpr int kMaxSides = 1000;
  /// Nurbs only: the patch in local coordinates, shared by copies (a search copies trees
  /// often; a mutation builds a new patch rather than editing one in place).
  std::shared_ptr<const BSplineSurface> patch;

  static Primitive3D box(double cx, double cy, double cz, double sx, double sy, double sz,
                         const Quaternion& rotation = {});
  static Primitive3D sphere(double cx, double cy, double cz, double r);
  static Primitive3D cylinder(double cx, double cy, double cz, double r, double height,
                              const Quaternion& rotation = {});
  static Primitive3D cone(double cx, double cy, double cz, double r1, double r2, double height,
                          const Quaternion& rotation = {});
  static Primitive3D ellipsoid(double cx, double cy, double cz, double rx, double ry, double rz,
                               const Quaternion& rotation = {});
  static Primitive3D torus(double cx, double cy, double cz, double major_r, double minor_r,
                           const Quaternion& rotation = {});
  static Primitive3D prism(double cx, double cy, double cz, double w, double h, double depth,
                           double apex = 0, const Quaternion& rotation = {});
  static Primitive3D rounded_box(double cx, double cy, double cz, double sx, double sy, double sz,
                                 double corner, const Quaternion& rotation = {});
  /// A NURBS terminal whose floor centre is (cx, cy, cz); `surface` is a height field over a
  /// rectangle centred on the local origin (BSplineSurface::height_field with x0 = -x1,
  /// y0 = -y1). Throws std::invalid_argument for any other surface.
  static Primitive3D nurbs(double cx, double cy, double cz, BSplineSurface surface,
                           const Quaternion& rotation = {});

  /// Exact volume of the continuous solid.
  double volume() const;
  /// Whether the point lies inside (boundary counts as inside), tested pointwise in the local
  /// frame; rasterize() sets a voxel exactly when this holds at its centre (up to rounding at
  /// points within ~1e-12 of the surface).
  bool contains(double x, double y, double z) const;
  /// Signed Euclidean distance to the surface, negative inside. Exact for every kind except
  /// the ellipsoid, where it is |q|(|q| - 1)/|q'| with q = local / semi-axes and
  /// q' = local / semi-axes^2: zero exactly on the surface, the right sign everywhere, exact
  /// for a sphere and first-order accurate near the surface; and the polygonal Cone (a
  /// pyramid frustum), where it is the largest signed distance to the planes of its faces:
  /// exact inside and wherever the nearest point is inside a face, an underestimate where it is
  /// an edge or a corner (a polygonal Cylinder is exact: the polygon's 2D distance combined
  /// with the z slab as an extrusion's, and so is the RoundedBox with the rounded rectangle's).
  double signed_distance(double x, double y, double z) const;
  /// signed_distance at each of `n` points, into `out` (the rotation applied once).
  void signed_distances(const Vec3* points, std::size_t n, double* out) const;
  /// Outward unit normal: the normalised gradient of signed_distance (central differences, so
  /// at edges and corners it averages the faces). {0, 0, 0} where the gradient vanishes.
  Vec3 normal_at(double x, double y, double z) const;
  /// Model point -> local frame.
  Vec3 to_local(double x, double y, double z) const;
  /// contains and signed_distance of a point already in the local frame.
  bool contains_local(const Vec3& local) const;
  double signed_distance_local(const Vec3& local) const;
  /// Tight axis-aligned bounds of the rotated solid.
  Bounds3 bounds() const;
  /// Whether the cross-section is a regular polygon (a Cylinder or Cone with sides >= 3).
  bool is_polygonal() const {
    return sides > 0 && (kind == PrimitiveKind3D::Cylinder || kind == PrimitiveKind3D::Cone);
  }
  /// Keeps sizes positive, tied sizes equal, r <= R for tori, the quaternion unit, sides 0 or
  /// in [3, kMaxSides] for Cylinder and Cone and 0 for the other kinds, a RoundedBox's corner
  /// in (0, min(sx, sy) / 2] (0 for the other kinds); called after every parameter change.
  void normalize();
  bool operator==(const Primitive3D& o) const;
  bool operator!=(const Primitive3D& o) const { return !(*this == o); }
};

/// Which 3D primitive kinds the matcher and the search may use.
struct PrimitiveSet3D {
  unsigned bits = 0;
  /// What "all" names: every analytic kind but the rounded box (and not the NURBS terminal,
  /// which only `csgfit points` fits). The rounded box is named on its own: the searches draw
  /// from this set, and a fit asked for "all" stays the fit it was before the rounded box.
  static PrimitiveSet3D all();
  /// The kinds seed 003 matches by moments: box, sphere, cylinder, cone, ellipsoid, prism (not
  /// the torus, nor the rounded box: moments do not tell its corner from its sizes).
  static PrimitiveSet3D matchable();
  /// Comma-separated names as primitive_kind3d_from_string takes them, or "all"; throws
  /// std::invalid_argument naming a bad name or an empty list.
  static PrimitiveSet3D parse(const std::string& list);
  bool has(PrimitiveKind3D k) const { return (bits >> static_cast<unsigned>(k)) & 1u; }
  void add(PrimitiveKind3D k) { bits |= 1u << static_cast<unsigned>(k); }
  bool empty() const { return bits == 0; }
};

/// The set without the NURBS terminal: what the fits that have no patch to fit may use.
PrimitiveSet3D analytic_kinds(PrimitiveSet3D set);

/// Indices into Primitive3D::dims that are free parameters of the kind (a sphere has one, a
/// cylinder two: {0, 2}, a torus two: {0, 1}); returns how many were written. A RoundedBox has
/// its three sizes and `corner` besides (has_free_corner).
int free_dims(PrimitiveKind3D kind, int out[3]);
/// Whether the kind has a free `corner` radius besides its free dims (the RoundedBox).
inline bool has_free_corner(PrimitiveKind3D kind) { return kind == PrimitiveKind3D::RoundedBox; }
/// Whether turning a primitive of this kind about its local z axis leaves it unchanged when it
/// is round (cylinder, cone, torus, sphere).
bool is_axially_symmetric(PrimitiveKind3D kind);
/// Whether turning this primitive about its local z axis leaves it unchanged: its kind is, and
/// it is not polygonal (a polygon's turn about its axis is its phase).
bool is_axially_symmetric(const Primitive3D& p);

/// Scan-converts p into `out`: a voxel is set exactly when its centre lies inside p. Clears
/// `out` first. Works per x-row (j, k) inside p's bounds, from the analytic x-interval(s) of
/// p on that line (one for convex kinds, up to two for the torus; a polygonal Cylinder or Cone
/// is the intersection of the half-spaces of its faces, a RoundedBox the hull of its two
/// crossed slabs and four corner discs).
void rasterize(const Primitive3D& p, VoxelGrid& out);
/// Where the line o + t d (d of unit length) lies inside p: up to four sorted, disjoint
/// t-intervals [lo[i], hi[i]], solved exactly for the analytic kinds (as rasterize does a row)
/// and for a NURBS terminal seen along its local vertical (seed 004's z-ray); a tilted patch is
/// sampled and its crossings bisected. Returns how many were written.
int line_intervals(const Primitive3D& p, const Vec3& o, const Vec3& d, double lo[4], double hi[4]);
/// rasterize() without the clearing: sets p's voxels and leaves every other bit as it was
/// (the incremental evaluator clears only the rows it is about to redraw).
void rasterize_into(const Primitive3D& p, VoxelGrid& out);

}  // namespace csgfit
