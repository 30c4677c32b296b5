// The exact OpenCASCADE solid of each primitive in its local frame (primitive3d.h), and the
// checks of its numbers: what the STEP writer places and combines.
#include "step_solids.h"

#include <BRepAlgoAPI_Common.hxx>
#include <BRepBuilderAPI_GTransform.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepOffsetAPI_ThruSections.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_GTrsf.hxx>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "csgfit/error.h"

namespace csgfit::step {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

double finite(double v, const char* what, const std::string& prim) {
  if (!std::isfinite(v) || std::fabs(v) > kMaxMagnitude)
    throw InputError("cannot write STEP: " + prim + " has a non-finite or out-of-range " + what);
  return v;
}
double positive(double v, const char* what, const std::string& prim) {
  finite(v, what, prim);
  if (!(v > 0)) throw InputError("cannot write STEP: " + prim + " has a " + what + " <= 0");
  return v;
}

// A closed polygon through the points.
TopoDS_Wire polygon_wire(const std::vector<gp_Pnt>& pts) {
  BRepBuilderAPI_MakePolygon poly;
  for (const gp_Pnt& p : pts) poly.Add(p);
  poly.Close();
  if (!poly.IsDone()) throw InputError("cannot write STEP: a degenerate polygon");
  return poly.Wire();
}

// A closed planar polygon, as a face.
TopoDS_Face polygon_face(const std::vector<gp_Pnt>& pts) {
  BRepBuilderAPI_MakeFace face(polygon_wire(pts), Standard_True);
  if (!face.IsDone()) throw InputError("cannot write STEP: a degenerate polygon");
  return face.Face();
}

TopoDS_Shape extrude(const TopoDS_Face& f, double height) {
  return BRepPrimAPI_MakePrism(f, gp_Vec(0, 0, height), Standard_True).Shape();
}

namespace {

// A clamped knot vector as OCCT wants it: the distinct knots and their multiplicities.
void knots_and_mults(const std::vector<double>& knots, std::vector<double>& distinct,
                     std::vector<int>& mults) {
  for (double k : knots) {
    if (!distinct.empty() && k == distinct.back()) {
      ++mults.back();
    } else {
      distinct.push_back(k);
      mults.push_back(1);
    }
  }
}

Handle(Geom_BSplineSurface) occt_surface(const BSplineSurface& s, const std::string& what) {
  const int nu = s.u_basis().count(), nv = s.v_basis().count();
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Vec3& c = s.control_point(i, j);
      poles.SetValue(i + 1, j + 1, gp_Pnt(finite(c[0], "control point", what),
                                          finite(c[1], "control point", what),
                                          finite(c[2], "control point", what)));
    }
  std::vector<double> ku, kv;
  std::vector<int> mu, mv;
  knots_and_mults(s.u_basis().knots(), ku, mu);
  knots_and_mults(s.v_basis().knots(), kv, mv);
  TColStd_Array1OfReal uk(1, static_cast<int>(ku.size())), vk(1, static_cast<int>(kv.size()));
  TColStd_Array1OfInteger um(1, static_cast<int>(mu.size())), vm(1, static_cast<int>(mv.size()));
  for (std::size_t i = 0; i < ku.size(); ++i) uk.SetValue(static_cast<int>(i) + 1, ku[i]), um.SetValue(static_cast<int>(i) + 1, mu[i]);
  for (std::size_t i = 0; i < kv.size(); ++i) vk.SetValue(static_cast<int>(i) + 1, kv[i]), vm.SetValue(static_cast<int>(i) + 1, mv[i]);
  return new Geom_BSplineSurface(poles, uk, vk, um, vm, s.u_basis().degree(), s.v_basis().degree());
}

// The exact patch as the top face, extruded down past the floor and cut at it: the prism's
// walls are the rectangle's, and the slab is wider than them so that only the floor is a new
// cut (coincident faces are where booleans go wrong).
TopoDS_Shape nurbs_solid(const Primitive3D& p, const std::string& what) {
  if (!p.patch) throw InputError("cannot write STEP: " + what + " has no patch");
  const double top = positive(p.dims[2], "top height", what);
  const double sx = positive(p.dims[0], "size x", what), sy = positive(p.dims[1], "size y", what);
  double low = 0;
  for (const Vec3& v : p.patch->net()) low = std::min(low, v[2]);
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(occt_surface(*p.patch, what), 1e-7).Face();
  const double drop = top - low + 0.1 * top;
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, -drop)).Shape();
  const double m = 0.05 * std::max(sx, sy);
  const TopoDS_Shape slab =
      BRepPrimAPI_MakeBox(gp_Pnt(-sx / 2 - m, -sy / 2 - m, 0), sx + 2 * m, sy + 2 * m, top + m).Shape();
  return BRepAlgoAPI_Common(prism, slab).Shape();
}

// The regular n-gon of circumradius r at height z, vertex 0 on +x (OpenSCAD's $fn-gon).
std::vector<gp_Pnt> regular_polygon(int n, double r, double z) {
  std::vector<gp_Pnt> pts;
  for (int i = 0; i < n; ++i)
    pts.emplace_back(r * std::cos(2 * kPi * i / n), r * std::sin(2 * kPi * i / n), z);
  return pts;
}

// A polygonal cylinder is the polygon extruded; a polygonal cone the ruled loft between its end
// polygons (a pointed end a vertex), whose vertices pair up at equal angles.
TopoDS_Shape polygonal_solid(const Primitive3D& p, const std::string& what) {
  const Vec3& d = p.dims;
  const bool cone = p.kind == PrimitiveKind3D::Cone;
  const double r1 = finite(d[0], "bottom radius", what);
  const double r2 = cone ? finite(d[1], "top radius", what) : r1;
  const double h = positive(d[2], "height", what);
  if (r1 < 0 || r2 < 0 || !(std::max(r1, r2) > 0))
    throw InputError("cannot write STEP: " + what + " has a negative or zero radius");
  if (p.sides < 3 || p.sides > Primitive3D::kMaxSides)
    throw InputError("cannot write STEP: " + what + " has " + std::to_string(p.sides) + " sides");
  if (r1 == r2) return extrude(polygon_face(regular_polygon(p.sides, r1, -h / 2)), h);
  BRepOffsetAPI_ThruSections loft(Standard_True, Standard_True);
  loft.CheckCompatibility(Standard_False);
  for (const auto& [r, z] : {std::pair{r1, -h / 2}, std::pair{r2, h / 2}}) {
    if (r > 0) loft.AddWire(polygon_wire(regular_polygon(p.sides, r, z)));
    else loft.AddVertex(BRepBuilderAPI_MakeVertex(gp_Pnt(0, 0, z)).Vertex());
  }
  loft.Build();
  if (!loft.IsDone())
    throw InputError("cannot write STEP: " + what + ": the loft of its end polygons failed");
  return loft.Shape();
}

// The rounded rectangle's wire at z = -sz/2, counter-clockwise: each side a line (none where
// a stadium's or a disc's side has no length) and each corner a quarter circle, extruded.
TopoDS_Shape rounded_box_solid(const Primitive3D& p, const std::string& what) {
  const double sx = positive(p.dims[0], "size x", what), sy = positive(p.dims[1], "size y", what);
  const double h = positive(p.dims[2], "size z", what);
  const double r = positive(p.corner, "corner", what);
  if (r > std::min(sx, sy) / 2 * (1 + 1e-12))
    throw InputError("cannot write STEP: " + what + " has a corner over half its smaller side");
  const double a = sx / 2, b = sy / 2, ca = std::max(a - r, 0.0), cb = std::max(b - r, 0.0);
  const double z = -h / 2;
  BRepBuilderAPI_MakeWire wire;
  // From the end of the side before each corner: (x, y) of the side's start and end, then the
  // corner's centre and the arc's end.
  const double sides[4][8] = {{a, -cb, a, cb, ca, cb, ca, b},
                              {ca, b, -ca, b, -ca, cb, -a, cb},
                              {-a, cb, -a, -cb, -ca, -cb, -ca, -b},
                              {-ca, -b, ca, -b, ca, -cb, a, -cb}};
  for (const auto& s : sides) {
    const gp_Pnt from(s[0], s[1], z), to(s[2], s[3], z), end(s[6], s[7], z);
    if (from.Distance(to) > 1e-9 * std::max(sx, sy)) wire.Add(BRepBuilderAPI_MakeEdge(from, to).Edge());
    const gp_Circ arc(gp_Ax2(gp_Pnt(s[4], s[5], z), gp::DZ()), r);
    wire.Add(BRepBuilderAPI_MakeEdge(arc, to, end).Edge());
  }
  if (!wire.IsDone()) throw InputError("cannot write STEP: " + what + ": its outline does not close");
  BRepBuilderAPI_MakeFace face(wire.Wire(), Standard_True);
  if (!face.IsDone()) throw InputError("cannot write STEP: " + what + ": its outline is no face");
  return extrude(face.Face(), h);
}

}  // namespace

TopoDS_Shape local_solid(const Primitive3D& p, const std::string& what) {
  const Vec3& d = p.dims;
  if (p.is_polygonal()) return polygonal_solid(p, what);
  switch (p.kind) {
    case PrimitiveKind3D::Box: {
      const double x = positive(d[0], "size x", what), y = positive(d[1], "size y", what),
                   z = positive(d[2], "size z", what);
      return BRepPrimAPI_MakeBox(gp_Pnt(-x / 2, -y / 2, -z / 2), x, y, z).Shape();
    }
    case PrimitiveKind3D::Sphere:
      return BRepPrimAPI_MakeSphere(positive(d[0], "radius", what)).Shape();
    case PrimitiveKind3D::Cylinder: {
      const double r = positive(d[0], "radius", what), h = positive(d[2], "height", what);
      return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -h / 2), gp::DZ()), r, h).Shape();
    }
    case PrimitiveKind3D::Cone: {
      const double r1 = finite(d[0], "bottom radius", what), r2 = finite(d[1], "top radius", what);
      const double h = positive(d[2], "height", what);
      if (r1 < 0 || r2 < 0 || !(std::max(r1, r2) > 0))
        throw InputError("cannot write STEP: " + what + " has a negative or zero radius");
      const gp_Ax2 axis(gp_Pnt(0, 0, -h / 2), gp::DZ());
      // OCCT refuses a cone whose radii are equal (it has no apex); that is a cylinder.
      if (std::fabs(r1 - r2) <= 1e-12 * std::max(r1, r2))
        return BRepPrimAPI_MakeCylinder(axis, (r1 + r2) / 2, h).Shape();
      return BRepPrimAPI_MakeCone(axis, r1, r2, h).Shape();
    }
    case PrimitiveKind3D::Ellipsoid: {
      const double a = positive(d[0], "x semi-axis", what), b = positive(d[1], "y semi-axis", what),
                   c = positive(d[2], "z semi-axis", what);
      if (a == b && b == c) return BRepPrimAPI_MakeSphere(a).Shape();
      // OCCT has no ellipsoid primitive: a unit sphere under a non-uniform scale (the sphere
      // becomes a B-spline surface; volume exact up to the B-spline fit, ~1e-9 relative).
      gp_GTrsf scale;
      scale.SetVectorialPart(gp_Mat(a, 0, 0, 0, b, 0, 0, 0, c));
      return BRepBuilderAPI_GTransform(BRepPrimAPI_MakeSphere(1.0).Shape(), scale, Standard_True)
          .Shape();
    }
    case PrimitiveKind3D::Torus: {
      const double big = positive(d[0], "major radius", what);
      double small = positive(d[1], "minor radius", what);
      if (small > big * (1 + 1e-9))
        throw InputError("cannot write STEP: " + what + " has a minor radius above its major radius");
      // A horn torus (r = R) touches its own axis, a point where the surface is singular and
      // BRepCheck rejects the solid; 1e-6 thinner keeps it valid and changes the volume by 1e-6.
      small = std::min(small, big * (1 - 1e-6));
      return BRepPrimAPI_MakeTorus(big, small).Shape();
    }
    case PrimitiveKind3D::TriangularPrism: {
      const double w = positive(d[0], "width", what), h = positive(d[1], "height", what),
                   depth = positive(d[2], "depth", what);
      const double apex = finite(p.apex, "apex", what);
      const double z = -depth / 2;
      return extrude(polygon_face({gp_Pnt(-w / 2, -h / 2, z), gp_Pnt(w / 2, -h / 2, z),
                                   gp_Pnt(apex * w / 2, h / 2, z)}),
                     depth);
    }
    case PrimitiveKind3D::Nurbs: return nurbs_solid(p, what);
    case PrimitiveKind3D::RoundedBox: return rounded_box_solid(p, what);
  }
  throw InputError("cannot write STEP: unknown primitive kind");
}

}  // namespace csgfit::step
