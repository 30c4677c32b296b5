"""A result's shared dimensions (the JSON's "shared_dimensions": one radius for a row of equal
holes, one centre for concentric circles, one height for holes through a plate) as spreadsheet
cells that every primitive using them refers to, so that editing one cell changes each of them.

A member whose value in the tree no longer equals the shared value (a hand-edited JSON) keeps
its own number: the tree's values are the truth.
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, Sequence, Tuple

#: What each shared field drives on the object holding a primitive's dimensions (part_objects):
#: a circle's Part::Cylinder, a rectangle's Part::Box, an ellipse's Part::Ellipse curve.
_PROPERTY = {
    ("circle", "r"): "Radius",
    ("circle", "cx"): "Placement.Base.x",
    ("circle", "cy"): "Placement.Base.y",
    ("ellipse", "cx"): "Placement.Base.x",
    ("ellipse", "cy"): "Placement.Base.y",
    ("rectangle", "w"): "Length",
    ("rectangle", "h"): "Width",
    ("sphere", "r"): "Radius",
    ("cylinder", "r"): "Radius",
    ("cylinder", "h"): "Height",
}

_FIELDS = {field for _, field in _PROPERTY}


def _uses(entry: Dict[str, Any]) -> List[Tuple[int, str]]:
    """The entry's (leaf, field) pairs that can be tied; malformed ones are left out."""
    out = []
    for use in entry.get("uses") or []:
        if (isinstance(use, dict) and isinstance(use.get("leaf"), int)
                and use.get("field") in _FIELDS):
            out.append((use["leaf"], use["field"]))
    return out


def _valid(entry: Any) -> bool:
    return (isinstance(entry, dict) and isinstance(entry.get("name"), str)
            and entry["name"].isidentifier() and isinstance(entry.get("uses"), list)
            and isinstance(entry.get("value"), (int, float))
            and math.isfinite(float(entry["value"])) and bool(_uses(entry)))


def sheet_rows(shared: Sequence[Any]) -> List[Tuple[str, str, str]]:
    """(title, value, alias) rows of the parameter sheet, one per shared dimension."""
    rows = []
    for entry in shared:
        if _valid(entry):
            rows.append((f"Shared {entry['name']} (mm)", f"={float(entry['value'])!r}mm",
                         entry["name"]))
    return rows


def bind(sheet, shared: Sequence[Any], primitives: Sequence[Tuple[Dict[str, Any], Any, Any]]) -> int:
    """Ties each use's property to its shared cell (primitives: PartTree.primitives, in the
    tree's pre-order, which the JSON's leaf indices count). Returns the number of ties made."""
    tied = 0
    for entry in shared:
        if not _valid(entry):
            continue
        value = float(entry["value"])
        for leaf, field in _uses(entry):
            if not 0 <= leaf < len(primitives):
                continue
            d, holder, _ = primitives[leaf]
            prop = _PROPERTY.get((d.get("type"), field))
            own = d.get(field)
            # A polygonal cylinder's Part::Prism has a Circumradius, no Radius: the solver never
            # shares a polygon's radius with a circle's, but a hand-edited document may.
            if prop is None or not isinstance(own, (int, float)) \
                    or prop.split(".")[0] not in holder.PropertiesList:
                continue
            if not math.isclose(float(own), value, rel_tol=1e-9, abs_tol=1e-12):
                continue
            holder.setExpression(prop, f"{sheet.Name}.{entry['name']}")
            tied += 1
    return tied
