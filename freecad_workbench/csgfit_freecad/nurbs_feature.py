"""The NURBS terminal of seed 004 (JSON leaf "type": "nurbs") as a parametric FreeCAD feature.

In its local frame (the Placement: the leaf's centre and rotation) the terminal is a height field
z = S(x, y) over the rectangle |x| <= SizeX/2, |y| <= SizeY/2, S a non-rational tensor-product
B-spline with clamped knots on [0, 1]; the solid is { in the rectangle, 0 <= z <= S(x, y) }, the
floor being the local plane z = 0. Every number of the patch is a property (DegreeU/V, KnotsU/V,
CountU/V, ControlPoints, SizeX/Y), so editing one control point recomputes the face and the solid.

The control points are the B-spline's poles as they are (P_ij = ControlPoints[i + CountU * j],
u along local x): the top of the solid is the exact Part.BSplineSurface of the JSON, the one the
STEP writer gives OpenCASCADE (as one face per knot span, see _span_faces). When each column of
poles keeps one x and each row one y, increasing from side to side of the rectangle (as the solver
places them: at the Greville abscissae or equally spaced) it is exactly the solver's height field
z = S(x, y); x and y of a pole may be edited too, as long as the net stays a grid over the
rectangle (a folded net makes no solid).
"""

from __future__ import annotations

from typing import Any, Dict, List, Sequence, Tuple

import FreeCAD as App

from .feature_proxy import PropertyProxy

TYPE_ID = "Part::FeaturePython"
#: OpenCASCADE's largest B-spline degree (Geom_BSplineSurface::MaxDegree).
MAX_DEGREE = 25


class NetError(ValueError):
    """The patch's numbers do not make a clamped B-spline surface (the message says why)."""


def knot_multiplicities(knots: Sequence[float], count: int, degree: int,
                        name: str) -> Tuple[List[float], List[int]]:
    """(distinct knots, multiplicities) of a clamped knot vector on [0, 1] for `count` control
    points of `degree`: count + degree + 1 non-decreasing knots, the first and last degree + 1 of
    them 0 and 1, interior knots repeated at most degree times (a higher multiplicity would tear
    the surface apart, which OpenCASCADE refuses)."""
    if not 1 <= degree <= MAX_DEGREE:
        raise NetError(f"degree {name} must be 1 .. {MAX_DEGREE}")
    if count <= degree:
        raise NetError(f"{name}: {count} control points need more than the degree {degree}")
    if len(knots) != count + degree + 1:
        raise NetError(f"knots {name}: {len(knots)} knots, expected {count} + {degree} + 1")
    ends = list(knots[:degree + 1]) + list(knots[-degree - 1:])
    if ends != [0.0] * (degree + 1) + [1.0] * (degree + 1):
        raise NetError(f"knots {name} must be clamped on [0, 1] (degree + 1 zeros and ones)")
    distinct, mults = [], []
    for k in knots:
        if distinct and k < distinct[-1]:
            raise NetError(f"knots {name} must not decrease")
        if distinct and k == distinct[-1]:
            mults[-1] += 1
        else:
            distinct.append(float(k))
            mults.append(1)
    if max(mults[1:-1], default=0) > degree:
        raise NetError(f"knots {name}: an interior knot repeats more than {degree} times")
    return distinct, mults


def bspline_surface(degree_u: int, degree_v: int, knots_u, knots_v, count_u: int, count_v: int,
                    points):
    """The Part.BSplineSurface of a control net (App.Vectors, u index fastest)."""
    import Part

    if len(points) != count_u * count_v:
        raise NetError(f"{len(points)} control points, expected {count_u} x {count_v}")
    ku, mu = knot_multiplicities(knots_u, count_u, degree_u, "u")
    kv, mv = knot_multiplicities(knots_v, count_v, degree_v, "v")
    # Part wants poles[i][j], i along u: the JSON's P_ij = points[i + nu * j].
    poles = [[App.Vector(points[i + count_u * j]) for j in range(count_v)]
             for i in range(count_u)]
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots(poles, mu, mv, ku, kv, False, False, degree_u, degree_v)
    return surface


def _box_sides(points, size_x: float, size_y: float, count_u: int, count_v: int, margin: float):
    """((x0, x1, y0, y1) of the box that trims the patch to the rectangle, whether any side of
    it trims at all). A side where the net's border row lies on the rectangle's side and no pole
    lies beyond it needs no trimming (the patch's convex hull stays inside): that side of the box
    moves out by `margin`, so the box never shares a face with the patch's wall (coincident
    faces are where OCCT's booleans fail)."""
    tol = 1e-9 * max(size_x, size_y)
    xs = [p.x for p in points]
    ys = [p.y for p in points]
    rows = {"x0": [points[count_u * j].x for j in range(count_v)],
            "x1": [points[count_u - 1 + count_u * j].x for j in range(count_v)],
            "y0": [points[i].y for i in range(count_u)],
            "y1": [points[i + count_u * (count_v - 1)].y for i in range(count_u)]}
    sides, trims = [], False
    for key, limit, coords, sign in (("x0", -size_x / 2, xs, -1), ("x1", size_x / 2, xs, 1),
                                     ("y0", -size_y / 2, ys, -1), ("y1", size_y / 2, ys, 1)):
        on_side = all(abs(c - limit) <= tol for c in rows[key])
        inside = all(sign * (c - limit) <= tol for c in coords)
        sides.append(limit + sign * margin if on_side and inside else limit)
        trims = trims or not (on_side and inside)
    return sides, trims


def _span_faces(surface):
    """The patch as one face per knot span (its polynomial pieces, all on the one B-spline
    surface). Why not one face: OpenCASCADE integrates a face's volume with one Gauss rule over
    the whole face, which is 0.2 to 0.4 % off for a bicubic patch of a dozen spans; over single
    spans the rule is exact."""
    ku, kv = surface.getUKnots(), surface.getVKnots()
    return [surface.toShape(u0, u1, v0, v1) for u0, u1 in zip(ku, ku[1:])
            for v0, v1 in zip(kv, kv[1:])]


def _walls(surface, floor: float):
    """(vertical wall faces, floor edges) from the patch's four border curves down to z = floor,
    span by span as the top faces. A border's projection is the curve with its poles' z set to
    the floor (a projection is affine, so it is exactly the projected curve)."""
    import Part

    walls, floor_edges = [], []
    ku, kv = surface.getUKnots(), surface.getVKnots()
    for border, knots in ((surface.uIso(0.0), kv), (surface.uIso(1.0), kv),
                          (surface.vIso(0.0), ku), (surface.vIso(1.0), ku)):
        below = border.copy()
        for k, pole in enumerate(border.getPoles(), start=1):
            below.setPole(k, App.Vector(pole.x, pole.y, floor))
        for a, b in zip(knots, knots[1:]):
            # Edges of the curves themselves, not of a face: each keeps the curve's own
            # direction, so the ruled face is not twisted.
            edge = below.toShape(a, b)
            floor_edges.append(edge)
            walls.append(Part.makeRuledSurface(border.toShape(a, b), edge))
    return walls, floor_edges


def _closed_solid(faces):
    """The solid bounded by faces that meet edge to edge (sewn into one closed shell)."""
    import Part

    sewn = Part.Compound(faces)
    sewn.sewShape(1e-7)
    shells = sewn.Shells
    if len(shells) != 1 or not shells[0].isClosed():
        raise NetError("the patch's faces do not close into a solid (does its border fold?)")
    solid = Part.Solid(shells[0])
    if solid.Volume < 0:  # a net running against its axes makes an inward shell
        solid.reverse()
    return solid


def solid_under(surface, points, size_x: float, size_y: float, count_u: int, count_v: int):
    """The solid { in the rectangle, 0 <= z <= S } in the local frame: the patch, vertical walls
    from its border down to a floor, and the planar floor. When the net's border is the
    rectangle's and every pole is above z = 0 (the solver's case) that floor is z = 0 and the
    solid is exact without a boolean. Otherwise the floor goes below z = 0 and the box from
    z = 0 to above the patch over the rectangle cuts it: that trims the patch to the rectangle
    and drops what lies below z = 0."""
    import Part

    if not (size_x > 0 and size_y > 0):
        raise NetError("SizeX and SizeY must be > 0")
    zs = [p.z for p in points]
    if max(zs) <= 0:
        raise NetError("every control point is at or below the floor (z <= 0): no solid")
    top, low = max(zs), min(min(zs), 0.0)
    margin = 0.1 * max(size_x, size_y, top - low)
    (x0, x1, y0, y1), trims = _box_sides(points, size_x, size_y, count_u, count_v, margin)
    cut = trims or min(zs) <= 0
    floor = low - margin if cut else 0.0
    walls, floor_edges = _walls(surface, floor)
    bottom = Part.Face(Part.Wire(Part.__sortEdges__(floor_edges)))
    solid = _closed_solid(_span_faces(surface) + walls + [bottom])
    if cut:
        box = Part.makeBox(x1 - x0, y1 - y0, top + margin, App.Vector(x0, y0, 0))
        solids = solid.common(box).Solids
        if not solids:
            raise NetError("the patch lies outside its rectangle or below its floor: no solid")
        solid = solids[0] if len(solids) == 1 else Part.makeCompound(solids)
    if not solid.isValid():
        raise NetError("the patch does not make a valid solid (does its control net fold?)")
    return solid


# ---- the feature --------------------------------------------------------------------------


class NurbsTerminal(PropertyProxy):
    """Proxy of the csgfit NURBS terminal: execute() rebuilds the B-spline face and the solid
    under it from the properties."""

    PROPERTIES = (
        ("App::PropertyInteger", "DegreeU", "Degree of the patch along u (local x); 3 = cubic"),
        ("App::PropertyInteger", "DegreeV", "Degree of the patch along v (local y); 3 = cubic"),
        ("App::PropertyInteger", "CountU", "Control points along u (local x)"),
        ("App::PropertyInteger", "CountV", "Control points along v (local y)"),
        ("App::PropertyFloatList", "KnotsU",
         "Clamped knot vector along u on [0, 1] (CountU + DegreeU + 1 knots)"),
        ("App::PropertyFloatList", "KnotsV",
         "Clamped knot vector along v on [0, 1] (CountV + DegreeV + 1 knots)"),
        ("App::PropertyVectorList", "ControlPoints",
         "CountU x CountV poles in the local frame, u index fastest; z = height above the floor"),
        ("App::PropertyLength", "SizeX", "Width of the rectangle along local x (centred)"),
        ("App::PropertyLength", "SizeY", "Depth of the rectangle along local y (centred)"),
    )
    GROUP = "NURBS terminal"

    def execute(self, obj):
        points = list(obj.ControlPoints)
        surface = bspline_surface(obj.DegreeU, obj.DegreeV, list(obj.KnotsU), list(obj.KnotsV),
                                  obj.CountU, obj.CountV, points)
        shape = solid_under(surface, points, float(obj.SizeX), float(obj.SizeY), obj.CountU,
                            obj.CountV)
        shape.Placement = obj.Placement
        obj.Shape = shape


def is_nurbs_terminal(obj) -> bool:
    return isinstance(getattr(obj, "Proxy", None), NurbsTerminal)


def make_nurbs(doc, name: str, leaf: Dict[str, Any]):
    """A NURBS terminal feature from the leaf's patch: leaf has "degree" [p, q], "counts"
    [nu, nv], "knots_u", "knots_v", "control_points" [[x, y, z], ...] (local, u fastest) and
    "size" [sx, sy, ...], already checked to be numbers of the right shapes. The patch itself is
    checked here (NetError); the caller sets the Placement."""
    (p, q), (nu, nv) = leaf["degree"], leaf["counts"]
    points = [App.Vector(*c) for c in leaf["control_points"]]
    # Built once before the object exists, so a bad patch leaves nothing in the document.
    bspline_surface(p, q, leaf["knots_u"], leaf["knots_v"], nu, nv, points)
    obj = doc.addObject(TYPE_ID, name)
    NurbsTerminal(obj)
    obj.DegreeU, obj.DegreeV, obj.CountU, obj.CountV = p, q, nu, nv
    obj.KnotsU, obj.KnotsV = leaf["knots_u"], leaf["knots_v"]
    obj.ControlPoints = points
    obj.SizeX, obj.SizeY = leaf["size"][0], leaf["size"][1]
    return obj
