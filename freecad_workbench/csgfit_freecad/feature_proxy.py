"""The part every csgfit Part::FeaturePython proxy shares (the NURBS terminal, the rounded box,
its section the rounded rectangle): its properties added when the feature is made, and nothing
of its own to save."""

from __future__ import annotations

from typing import Tuple


class PropertyProxy:
    """A proxy whose feature holds everything in its properties: PROPERTIES, (property type,
    name, tooltip) in the property editor's order, under the heading GROUP. Subclasses add
    execute()."""

    PROPERTIES: Tuple[Tuple[str, str, str], ...] = ()
    GROUP = ""

    def __init__(self, obj):
        for kind, name, tip in self.PROPERTIES:
            obj.addProperty(kind, name, self.GROUP, tip)
        obj.Proxy = self

    # FreeCAD 0.20 saves a proxy through __getstate__ / __setstate__, later versions through
    # dumps / loads; there is nothing to save but the properties, which FreeCAD keeps itself.
    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    dumps, loads = __getstate__, __setstate__
