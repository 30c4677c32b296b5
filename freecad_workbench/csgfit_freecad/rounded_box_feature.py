"""The rounded box (JSON leaf "type": "rounded_box") as a parametric FreeCAD feature, and its
section, the rounded rectangle, as one (a sweep's profile face, sweep_objects.py).

In its local frame (the Placement: the leaf's centre and rotation) the solid is the box
|x| <= Length/2, |y| <= Width/2, |z| <= Height/2 whose four edges along z are rounded with
Radius: its outline of four lines and four quarter circles, extruded. Editing any of the four
properties recomputes it. The rounded rectangle is that outline's face at z = 0.

Why not a Part::Box with a Part::Fillet of its vertical edges, FreeCAD's own objects: the
commonest rounded box is the stadium of a slot, Radius = half the Width, where two fillets meet
with no face between them; OpenCASCADE refuses that fillet and FreeCAD 0.20 leaves the Fillet
invalid. The outline leaves out a side of no length instead.
"""

from __future__ import annotations

import math
from typing import Sequence

import FreeCAD as App

from .feature_proxy import PropertyProxy

TYPE_ID = "Part::FeaturePython"


class OutlineError(ValueError):
    """The sizes do not make a rounded box (the message says why)."""


def rounded_rectangle_face(length: float, width: float, radius: float, z: float = 0.0):
    """The face of the outline centred on the z axis at height z: counter-clockwise, each side
    a line (none where a stadium's or a disc's side has no length) and each corner a quarter
    circle about its centre."""
    import Part

    if not (length > 0 and width > 0):
        raise OutlineError("Length and Width must be > 0")
    most = min(length, width) / 2
    if not (0 < radius <= most * (1 + 1e-12)):
        raise OutlineError("Radius must be > 0 and at most half the smaller of Length and Width")
    radius = min(radius, most)
    a, b = length / 2, width / 2
    ca, cb = max(a - radius, 0.0), max(b - radius, 0.0)
    centres = [App.Vector(ca, cb, z), App.Vector(-ca, cb, z), App.Vector(-ca, -cb, z),
               App.Vector(ca, -cb, z)]
    edges = []
    # Corner k's arc runs from 90 k to 90 (k + 1) degrees; the side after it, square to the
    # arc's end direction u, runs from its end to the next arc's start.
    for k, centre in enumerate(centres):
        start = k * math.pi / 2
        arc = Part.Circle(centre, App.Vector(0, 0, 1), radius)
        edges.append(arc.toShape(start, start + math.pi / 2))
        u = App.Vector(math.cos(start + math.pi / 2), math.sin(start + math.pi / 2), 0) * radius
        side_from, side_to = centre + u, centres[(k + 1) % 4] + u
        if side_from.distanceToPoint(side_to) > 1e-9 * max(length, width):
            edges.append(Part.LineSegment(side_from, side_to).toShape())
    return Part.Face(Part.Wire(edges))


def rounded_box_solid(length: float, width: float, height: float, radius: float):
    """The solid centred on the origin: the outline's face at z = -height/2, extruded by
    height."""
    if not (length > 0 and width > 0 and height > 0):
        raise OutlineError("Length, Width and Height must be > 0")
    face = rounded_rectangle_face(length, width, radius, -height / 2)
    solid = face.extrude(App.Vector(0, 0, height))
    if not solid.isValid():
        raise OutlineError("the outline does not make a valid solid")
    return solid


class RoundedBox(PropertyProxy):
    """Proxy of the csgfit rounded box: execute() rebuilds the solid from the properties."""

    PROPERTIES = (
        ("App::PropertyLength", "Length", "Size along local x (centred)"),
        ("App::PropertyLength", "Width", "Size along local y (centred)"),
        ("App::PropertyLength", "Height", "Size along local z (centred)"),
        ("App::PropertyLength", "Radius",
         "Radius of the four edges along local z; half the smaller of Length and Width makes "
         "a stadium"),
    )
    GROUP = "Rounded box"

    def execute(self, obj):
        shape = rounded_box_solid(float(obj.Length), float(obj.Width), float(obj.Height),
                                  float(obj.Radius))
        shape.Placement = obj.Placement
        obj.Shape = shape


class RoundedRectangle(PropertyProxy):
    """Proxy of the csgfit rounded rectangle, a rounded box's section in a sweep's profile:
    execute() rebuilds the face from the properties."""

    PROPERTIES = (
        ("App::PropertyLength", "Length", "Size along local x (centred)"),
        ("App::PropertyLength", "Width", "Size along local y (centred)"),
        ("App::PropertyLength", "Radius",
         "Radius of the four corners; half the smaller of Length and Width makes a stadium"),
    )
    GROUP = "Rounded rectangle"

    def execute(self, obj):
        shape = rounded_rectangle_face(float(obj.Length), float(obj.Width), float(obj.Radius))
        shape.Placement = obj.Placement
        obj.Shape = shape


def is_rounded_box(obj) -> bool:
    return isinstance(getattr(obj, "Proxy", None), RoundedBox)


def is_rounded_rectangle(obj) -> bool:
    return isinstance(getattr(obj, "Proxy", None), RoundedRectangle)


def make_rounded_box(doc, name: str, size: Sequence[float], corner: float):
    """A rounded box feature of sizes [sx, sy, sz] and corner radius `corner`, checked here
    (OutlineError) before the object exists; the caller sets the Placement."""
    rounded_box_solid(size[0], size[1], size[2], corner)
    obj = doc.addObject(TYPE_ID, name)
    RoundedBox(obj)
    obj.Length, obj.Width, obj.Height = size
    obj.Radius = corner
    return obj


def make_rounded_rectangle(doc, name: str, length: float, width: float, corner: float):
    """A rounded rectangle feature (a face in its local xy plane, centred) of sides length and
    width and corner radius `corner`, checked here (OutlineError) before the object exists; the
    caller sets the Placement."""
    rounded_rectangle_face(length, width, corner)
    obj = doc.addObject(TYPE_ID, name)
    RoundedRectangle(obj)
    obj.Length, obj.Width = length, width
    obj.Radius = corner
    return obj
