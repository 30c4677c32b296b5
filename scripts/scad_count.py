"""What an OpenSCAD program is built of: its operations, $fn-prisms and leaf primitives.

bench_3d.py counts them in our .scad and in the designer's program side by side (a fit that
recovers the design uses the same kinds of operation, not a pile of boxes); random_parts.py
counts its programs' leaves and operations for the manifest. Text only: a flattened program
(OpenSCAD's .csg export, our .scad, a program without loops or modules) counts what renders.
"""

import re

# The operations a designer reaches for, in the order the tables list them, with the letter a
# table cell uses for each; "P" counts $fn-prisms (below).
OPERATIONS = (("linear_extrude", "L"), ("rotate_extrude", "R"), ("hull", "H"), ("offset", "O"),
              ("intersection", "I"), ("difference", "D"), ("union", "U"), ("fn_prism", "P"))
# A cylinder or circle with an explicit $fn this small is a prism the designer meant (a $fn = 6
# nut trap, an 8-gon polyhole), not a round part's facets.
FN_PRISM_MAX = 16
LEAF_PRIMITIVES = ("cube", "sphere", "cylinder", "polyhedron", "circle", "square", "polygon")
OPS_LEGEND = ("Operations: L linear_extrude, R rotate_extrude, H hull, O offset, I intersection, "
              "D difference, U union, P $fn-prism (a cylinder or circle with an explicit "
              "$fn <= %d); `group()` and transformations are not counted." % FN_PRISM_MAX)

_COMMENT_RE = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_OPERATION_RE = re.compile(r"\b(%s)\s*\(" % "|".join(name for name, _ in OPERATIONS[:-1]))
_ROUND_CALL_RE = re.compile(r"\b(?:cylinder|circle)\s*\(((?:[^()]|\([^()]*\))*)\)")
_FN_RE = re.compile(r"\$fn\s*=\s*([0-9.]+)")
_LEAF_RE = re.compile(r"\b(%s)\s*\(" % "|".join(LEAF_PRIMITIVES))


def scad_code(text):
    """The program without its comments: our .scad's Customizer headers and notes name
    operations ("difference") that the program may not use."""
    return _COMMENT_RE.sub("", text)


def scad_operations(text):
    """{operation: count} of an OpenSCAD program's text (a flattened one, such as OpenSCAD's
    .csg export or our .scad, counts what renders), zero counts left out."""
    code = scad_code(text)
    counts = {}
    for m in _OPERATION_RE.finditer(code):
        counts[m.group(1)] = counts.get(m.group(1), 0) + 1
    prisms = 0
    for m in _ROUND_CALL_RE.finditer(code):
        fn = _FN_RE.search(m.group(1))
        prisms += bool(fn and 3 <= float(fn.group(1)) <= FN_PRISM_MAX)
    if prisms:
        counts["fn_prism"] = prisms
    return counts


def scad_leaves(text):
    """How many leaf primitives (LEAF_PRIMITIVES) a flat program's text calls: the
    manifests' gt_primitives for a program without loops or modules."""
    return len(_LEAF_RE.findall(scad_code(text)))


def ops_text(counts):
    """A table cell for scad_operations(): "D2 I5 H8 L2" in OPERATIONS order; "none"."""
    parts = ["%s%d" % (letter, counts[name]) for name, letter in OPERATIONS if counts.get(name)]
    return " ".join(parts) or "none"


def program_operations(path):
    """scad_operations() of the program at `path`."""
    with open(path) as f:
        return scad_operations(f.read())
