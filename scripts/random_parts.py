#!/usr/bin/python3
"""Random designer-like OpenSCAD parts and their STL renders, for bench_3d.py --set random.

The printed and InverseCSG sets are fixed files, and a solver tuned on them may learn them
rather than parts. This writes fresh parts of the kinds people draw in OpenSCAD for printing and
machining, K of them for a seed:

  random_parts.py --seed N --count K --out DIR

DIR/part_NNN.scad (a flat program: no modules, loops or variables, so that its text is its
tree), DIR/part_NNN.stl (OpenSCAD's render) and DIR/manifest.json in the printed set's schema
({"models": [{name, kind: "random", mesh, gt, gt_primitives, gt_operations, source}]}).

Each part is a plate, a rounded plate, a block, an L-bracket, a turned part or two crossed
cylinders, with a random mix of bosses, through and blind holes ($fn = 6 nut traps, 8-gon
polyholes, counterbores, countersinks), square and obround slots and crossing holes; dimensions
in mm on a 0.5 mm raster, parts 10-150 mm, walls and features down to 2 mm; all axis-aligned
but for an occasional turn by a multiple of 45 or 90 degrees about one axis. A program whose
render is not one closed solid (OpenSCAD fails, or the STL has an open edge or two shells) is
drawn again from the next random numbers. The same seed gives the same programs, and so
the same solids (OpenSCAD may list an STL's triangles in another order from run to run).
Runs on Debian's /usr/bin/python3 with numpy and OpenSCAD.
"""

import argparse
import json
import math
import os
import random
import sys

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import bench_3d  # noqa: E402  (OpenSCAD to STL, the STL reader)
import scad_count  # noqa: E402  (the manifest's counts, as bench_3d.py counts them)

RASTER = 0.5   # every dimension and position a designer types
WALL = 2.0     # the thinnest wall and the smallest feature
OVERSHOOT = 1  # how far a cut reaches past the face it opens, as designers write it
MAX_DRAWS = 50  # draws per part before giving up (a bug, not bad luck)

# ----------------------------------------------------------------------------------------------
# Numbers and program text


class Draw:
    """The seed's random numbers, as the dimensions a designer would type."""

    def __init__(self, seed):
        self.rng = random.Random(seed)

    def mm(self, lo, hi):
        """A number on the raster in [lo, hi] (the first one at or above lo when there is
        none: a caller that cares checks it)."""
        first = math.ceil(lo / RASTER - 1e-9)
        last = math.floor(hi / RASTER + 1e-9)
        return RASTER * self.rng.randint(first, max(first, last))

    def even(self, lo, hi):
        """A length whose half is on the raster too: a size something is centred in."""
        return 2 * self.mm(lo / 2, hi / 2)

    def chance(self, p):
        return self.rng.random() < p

    def pick(self, options):
        return self.rng.choice(options)

    def weighted(self, table):
        """One value of [(weight, value)]."""
        return self.rng.choices([v for _, v in table], [w for w, _ in table])[0]


def num(v):
    """A number as a designer writes it: 12, 12.5, -1."""
    return "%g" % round(v, 4)


def on_raster(v):
    """v rounded to the raster."""
    return RASTER * round(v / RASTER)


def vec(*vs):
    return "[%s]" % ", ".join(num(v) for v in vs)


def node(name, args="", *children):
    """One statement of the program: name(args) with its children (none: a leaf); args is
    the text between the parentheses, or a vector (a tuple) of a transform."""
    return (name, args, children)


def translate(v, child):
    """translate(v) child; a translate of a translate is one, as a designer would write it."""
    if child[0] == "translate":
        v = tuple(a + b for a, b in zip(v, child[1]))
        child = child[2][0]
    return node("translate", tuple(v), child)


def rotate(v, child):
    return node("rotate", tuple(v), child)


def cube(x, y, z):
    return node("cube", vec(x, y, z))


def cylinder(d, h, fn=None, d2=None):
    """A cylinder standing on z = 0 (a cone with d2); fn: a designer's $fn-prism."""
    size = "d = %s" % num(d) if d2 is None else "d1 = %s, d2 = %s" % (num(d), num(d2))
    return node("cylinder", "h = %s, %s%s" % (num(h), size, "" if fn is None else
                                               ", $fn = %d" % fn))


def circle(d, at=(0, 0)):
    return translate(at, node("circle", "d = %s" % num(d)))


def emit(tree, depth=0):
    """The program lines of a tree; a statement of one child shares the child's line."""
    name, args, children = tree
    args = vec(*args) if isinstance(args, tuple) else args
    pad = "    " * depth
    if not children:
        return [pad + "%s(%s);" % (name, args)]
    if len(children) == 1:
        lines = emit(children[0], depth)
        return [pad + "%s(%s) %s" % (name, args, lines[0].lstrip())] + lines[1:]
    lines = [pad + "%s(%s) {" % (name, args)]
    for child in children:
        lines += emit(child, depth + 1)
    return lines + [pad + "}"]


def combine(body, adds, cuts):
    """body plus adds minus cuts, written as a designer would: difference() { union() {..} ..}."""
    solid = body if not adds else node("union", "", body, *adds)
    return solid if not cuts else node("difference", "", solid, *cuts)


# ----------------------------------------------------------------------------------------------
# Features on a face


class Face:
    """The top face of a plate: features are placed on [x0, x1] x [y0, y1] at z = top, the plate
    being `thickness` deep below it, each keeping a wall of WALL to the edges and to the
    others (`taken`: the discs already used)."""

    def __init__(self, x0, x1, y0, y1, bottom, top):
        self.x0, self.x1, self.y0, self.y1 = x0, x1, y0, y1
        self.bottom, self.top = bottom, top
        self.thickness = top - bottom
        self.taken = []

    def place(self, draw, r):
        """A free centre on the raster for a feature of radius r, or None after some tries."""
        for _ in range(30):
            x = draw.mm(self.x0 + r + WALL, self.x1 - r - WALL)
            y = draw.mm(self.y0 + r + WALL, self.y1 - r - WALL)
            if x + r + WALL > self.x1 or y + r + WALL > self.y1:
                return None  # the face is too small for it
            if all(math.hypot(x - u, y - v) >= r + s + WALL for u, v, s in self.taken):
                self.taken.append((x, y, r))
                return x, y
        return None


def through(face, x, y, d, fn=None, extra=0):
    """A hole through the plate (and `extra` above its face: through a boss)."""
    return translate((x, y, face.bottom - OVERSHOOT),
                     cylinder(d, face.thickness + extra + 2 * OVERSHOOT, fn))


def from_top(face, x, y, d, depth, fn=None, d2=None):
    """A cut `depth` deep into the face, reaching OVERSHOOT above it."""
    return translate((x, y, face.top - depth), cylinder(d, depth + OVERSHOOT, fn, d2))


def hole(draw, face):
    """A screw hole of one of the kinds designers draw: ([], cuts), or None when it did not
    fit. Cuts that need depth (blind, counterbore, nut trap) only in plates of 4 mm or more;
    they leave WALL of the plate under or over them."""
    deep = face.thickness >= 2 * WALL
    d = draw.mm(WALL, 10)
    kind = draw.weighted([(3, "through"), (2, "polyhole"), (2 if deep else 0, "blind"),
                          (2 if deep else 0, "counterbore"), (1, "countersink"),
                          (2 if deep else 0, "nut trap")])
    depth = draw.mm(WALL, face.thickness - WALL)
    sink = draw.mm(RASTER, max(RASTER, min(d / 2, face.thickness - 1)))
    # a countersink is a 90 degree cone from the hole's diameter, OVERSHOOT above the face
    outer = {"counterbore": d + draw.mm(2, 6), "countersink": d + 2 * (sink + OVERSHOOT),
             "nut trap": d + draw.mm(2, 4)}.get(kind, d)
    at = face.place(draw, outer / 2)
    if at is None:
        return None
    x, y = at
    cuts = {
        "through": lambda: [through(face, x, y, d)],
        "polyhole": lambda: [through(face, x, y, d, fn=8)],
        "blind": lambda: [from_top(face, x, y, d, depth)],
        "counterbore": lambda: [through(face, x, y, d), from_top(face, x, y, outer, depth)],
        "countersink": lambda: [through(face, x, y, d),
                                from_top(face, x, y, d, sink, d2=outer)],
        "nut trap": lambda: [through(face, x, y, d), translate(
            (x, y, face.bottom - OVERSHOOT), cylinder(outer, depth + OVERSHOOT, fn=6))],
    }[kind]()
    return [], cuts


def boss(draw, face):
    """A boss standing on the face (sometimes a cone, sometimes with a hole through it and the
    plate): (adds, cuts) or None."""
    d = draw.mm(2 * WALL + 2, 24)
    at = face.place(draw, d / 2)
    if at is None:
        return None
    x, y = at
    h = draw.mm(WALL, 20)
    top = d if not draw.chance(0.25) else draw.mm(2 * WALL, d - 1)
    adds = [translate((x, y, face.top), cylinder(d, h, d2=None if top == d else top))]
    cuts = []
    if top >= 3 * WALL and draw.chance(0.6):
        cuts.append(through(face, x, y, draw.mm(WALL, top - 2 * WALL), extra=h))
    return adds, cuts


def slot(draw, face):
    """A square through-slot or an obround one (linear_extrude of a hull of two circles, or a
    hull of two cylinders), sometimes turned by 45 or 90 degrees: ([], cuts) or None."""
    w = draw.even(WALL, 10)
    length = w + draw.even(1, 2 * w + 12)
    at = face.place(draw, math.hypot(w, length) / 2)
    if at is None:
        return None
    x, y = at
    h = face.thickness + 2 * OVERSHOOT
    kind = draw.pick(["square", "extruded obround", "hull obround"])
    if kind == "square":
        shape = translate((-length / 2, -w / 2, 0), cube(length, w, h))
    elif kind == "extruded obround":
        shape = node("linear_extrude", "height = %s" % num(h), node(
            "hull", "", circle(w, (-(length - w) / 2, 0)), circle(w, ((length - w) / 2, 0))))
    else:
        shape = node("hull", "", translate((-(length - w) / 2, 0, 0), cylinder(w, h)),
                     translate(((length - w) / 2, 0, 0), cylinder(w, h)))
    angle = draw.weighted([(3, 0), (1, 45), (1, 90)])
    if angle:
        shape = rotate((0, 0, angle), shape)
    return [], [translate((x, y, face.bottom - OVERSHOOT), shape)]


FEATURES = [(4, hole), (2, boss), (2, slot)]


def face_features(draw, face, count):
    """Up to `count` features on the face: (adds, cuts)."""
    adds, cuts = [], []
    for _ in range(count):
        got = draw.weighted(FEATURES)(draw, face)
        if got:
            adds += got[0]
            cuts += got[1]
    return adds, cuts


def crossing_hole(draw, axis, size, lo, hi):
    """A hole along `axis` (0 x, 1 y, 2 z) right through a box of `size`, its centre on the
    other two axes in [lo, hi] (per axis) with a wall of WALL around it, or None."""
    others = [a for a in range(3) if a != axis]
    room = min(hi[a] - lo[a] for a in others)
    if room < 3 * WALL:
        return None
    d = draw.mm(WALL, min(room - 2 * WALL, 16))  # (room >= 3 WALL: d >= WALL fits)
    centre = [0.0, 0.0, 0.0]
    for a in others:
        centre[a] = draw.mm(lo[a] + d / 2 + WALL, hi[a] - d / 2 - WALL)
    centre[axis] = -OVERSHOOT
    turn = {0: (0, 90, 0), 1: (-90, 0, 0), 2: (0, 0, 0)}[axis]
    shape = cylinder(d, size[axis] + 2 * OVERSHOOT, fn=draw.pick([None, None, 8]))
    return translate(centre, rotate(turn, shape) if axis != 2 else shape)


# ----------------------------------------------------------------------------------------------
# Parts


def plate(draw):
    """A rectangular plate with holes, bosses and slots."""
    x, y, t = draw.mm(20, 150), draw.mm(15, 100), draw.mm(WALL, 12)
    face = Face(0, x, 0, y, 0, t)
    adds, cuts = face_features(draw, face, draw.rng.randint(1, 6))
    return combine(cube(x, y, t), adds, cuts)


def rounded_plate(draw):
    """A plate whose outline is a rounded rectangle (hull of four circles, extruded)."""
    x, y, t = draw.mm(20, 120), draw.mm(15, 90), draw.mm(WALL, 10)
    r = draw.mm(WALL, min(x, y) / 4)
    corners = [circle(2 * r, (cx, cy)) for cx in (r, x - r) for cy in (r, y - r)]
    body = node("linear_extrude", "height = %s" % num(t), node("hull", "", *corners))
    face = Face(r / 2, x - r / 2, r / 2, y - r / 2, 0, t)
    adds, cuts = face_features(draw, face, draw.rng.randint(1, 5))
    return combine(body, adds, cuts)


def block(draw):
    """A block with holes crossing it along two or three axes (a connector, a bearing block),
    sometimes a few holes in its top, sometimes rounded by a sphere."""
    size = [draw.even(10, 60) for _ in range(3)]
    cuts = []
    for axis in draw.rng.sample(range(3), draw.pick([2, 3])):
        for _ in range(draw.pick([1, 1, 2])):
            cut = crossing_hole(draw, axis, size, [0, 0, 0], size)
            if cut:
                cuts.append(cut)
    body = cube(*size)
    if draw.chance(0.15):
        half = [s / 2 for s in size]
        ball = translate(half, node("sphere", "d = %s" % num(
            draw.mm(max(size) * 1.1, math.hypot(*size) - 1))))
        body = node("intersection", "", body, ball)
    return combine(body, [], cuts)


def bracket(draw):
    """An L-bracket: a base and an upright (sometimes a gusset between them), holes in both."""
    length, width, t = draw.mm(25, 100), draw.mm(15, 60), draw.mm(3, 10)
    height = draw.mm(20, 80)
    base, upright = cube(length, width, t), cube(t, width, height)
    adds = [upright]
    if draw.chance(0.5):
        g = draw.mm(t + 5, min(length, height) - 5)
        gt = draw.mm(WALL, t)
        tri = node("polygon", "points = [%s, %s, %s]" % (vec(0, 0), vec(g, 0), vec(0, g)))
        adds.append(translate((t, on_raster((width + gt) / 2), t), rotate(
            (90, 0, 0), node("linear_extrude", "height = %s" % num(gt), tri))))
    face = Face(t, length, 0, width, 0, t)
    more, cuts = face_features(draw, face, draw.rng.randint(1, 3))
    for _ in range(draw.rng.randint(0, 2)):  # holes through the upright, along x
        cut = crossing_hole(draw, 0, (t, width, height), [0, 0, t], [t, width, height])
        if cut:
            cuts.append(cut)
    return combine(base, adds + more, cuts)


def turned(draw):
    """A turned part: rotate_extrude of a stepped profile of squares (with now and then a bead,
    a circle on a step's side), a bore, sometimes a cross pin hole or a ball on top."""
    steps, z, profile = [], 0.0, []
    for _ in range(draw.rng.randint(1, 4)):
        r, h = draw.mm(3, 40), draw.even(WALL, 30)
        profile.append(translate((0, z), node("square", vec(r, h))))
        if draw.chance(0.3) and h >= 2 * WALL:
            profile.append(circle(draw.mm(WALL, min(h, r)), (r, z + h / 2)))
        steps.append((r, z, h))
        z += h
    body = node("rotate_extrude", "", *profile)
    adds, cuts = [], []
    radii = [r for r, _, _ in steps]
    if draw.chance(0.2):
        ball = draw.mm(2 * WALL, 2 * radii[-1])
        adds.append(translate((0, 0, z), node("sphere", "d = %s" % num(ball))))
    if min(radii) > 2 * WALL and draw.chance(0.7):
        bore = draw.mm(WALL, 2 * (min(radii) - WALL))
        cuts.append(translate((0, 0, -OVERSHOOT), cylinder(bore, z + 2 * OVERSHOOT)))
    r, z0, h = max(steps, key=lambda s: s[2])
    if h >= 3 * WALL and draw.chance(0.3):  # a pin hole across the tallest step's axis
        d = draw.mm(WALL, min(h - 2 * WALL, r))
        cuts.append(translate((0, -r - OVERSHOOT, z0 + h / 2), rotate(
            (-90, 0, 0), cylinder(d, 2 * (r + OVERSHOOT)))))
    return combine(body, adds, cuts)


def crossed_cylinders(draw):
    """A round bar with rounded ends: a cylinder intersected with a cylinder across it (or a
    D-shaft: with a box), a hole through it."""
    d, length = draw.even(8, 50), draw.even(10, 120)
    bar = cylinder(d, length)
    if draw.chance(0.7):
        cross = translate((0, d, length / 2), rotate((90, 0, 0), cylinder(
            draw.mm(max(length * 0.8, d + 2), max(length * 1.6, d + 2)), 2 * d)))
    else:
        flat = draw.mm(WALL, d / 3)
        cross = translate((-d, -d / 2 + flat, -OVERSHOOT), cube(2 * d, d, length + 2))
    body = node("intersection", "", bar, cross)
    cuts = []
    if d >= 3 * WALL and draw.chance(0.8):
        hd = draw.mm(WALL, d - 2 * WALL)
        cuts.append(translate((-d, 0, draw.mm(hd / 2 + WALL, length - hd / 2 - WALL)),
                              rotate((0, 90, 0), cylinder(hd, 2 * d))))
    return combine(body, [], cuts)


KINDS = [(3, plate), (2, rounded_plate), (2, block), (2, bracket), (2, turned),
         (1, crossed_cylinders)]


def random_part(draw):
    """(kind, tree) of one part, sometimes turned by 45 or 90 degrees about one axis."""
    kind = draw.weighted(KINDS)
    tree = kind(draw)
    if draw.chance(0.2):
        axis = draw.rng.randint(0, 2)
        angle = [0, 0, 0]
        angle[axis] = draw.pick([45, 90, 90, 180])
        tree = rotate(angle, tree)
    return kind.__name__, tree


# ----------------------------------------------------------------------------------------------
# Rendering and checking


def program_text(name, source, tree):
    """The .scad file: a comment saying where it comes from, the facet settings and the tree."""
    head = ["// %s: %s" % (name, source),
            "$fa = 6;", "$fs = 0.5;", ""]
    return "\n".join(head + emit(tree)) + "\n"


def solid_problem(tris):
    """Why the triangles are not one closed solid (an edge not shared by exactly two
    triangles, or several shells: pieces apart or a void inside), or None."""
    verts, ids = np.unique(tris.reshape(-1, 3), axis=0, return_inverse=True)
    ids = ids.reshape(-1, 3)
    edges = np.sort(np.concatenate([ids[:, [0, 1]], ids[:, [1, 2]], ids[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    if np.any(counts != 2):
        return "%d edges not shared by two triangles" % int(np.sum(counts != 2))
    parent = list(range(len(verts)))

    def root(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in edges:
        parent[root(a)] = root(b)
    shells = len({root(a) for a in range(len(verts))})
    return None if shells == 1 else "%d shells" % shells


def render_checked(scad, stl, timeout):
    """Renders scad to stl; the reason it is not a valid single solid, or None."""
    try:
        bench_3d.openscad_stl(scad, stl, timeout)
        return solid_problem(bench_3d.read_mesh(stl))
    except Exception as exc:  # OpenSCAD failed or timed out: draw again
        return str(exc)


def write_part(draw, out, index, seed, timeout):
    """Draws part `index` until its render is one solid; its manifest entry."""
    name = "part_%03d" % index
    scad, stl = os.path.join(out, name + ".scad"), os.path.join(out, name + ".stl")
    for attempt in range(MAX_DRAWS):
        kind, tree = random_part(draw)
        source = "scripts/random_parts.py --seed %d: part %d, %s (draw %d)" % (
            seed, index, kind, attempt + 1)
        text = program_text(name, source, tree)
        with open(scad, "w") as f:
            f.write(text)
        problem = render_checked(scad, stl, timeout)
        if problem is None:
            ops = scad_count.scad_operations(text)
            ops.pop("fn_prism", None)  # the manifest counts operations, as the printed set's
            return {"name": name, "kind": "random", "mesh": name + ".stl", "gt": name + ".scad",
                    "gt_primitives": scad_count.scad_leaves(text), "gt_operations": ops,
                    "source": source}
        print("random_parts: %s draw %d (%s) rejected: %s" % (name, attempt + 1, kind, problem),
              file=sys.stderr)
    raise SystemExit("random_parts: %s: no valid part in %d draws" % (name, MAX_DRAWS))


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--count", type=int, required=True)
    ap.add_argument("--out", required=True, help="directory for the parts and manifest.json")
    ap.add_argument("--openscad-timeout", type=float, default=300.0,
                    help="seconds per OpenSCAD render (default 300)")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if bench_3d.benchlib.missing_tool("random_parts", "openscad"):
        return 2
    os.makedirs(args.out, exist_ok=True)
    draw = Draw(args.seed)
    models = []
    for i in range(args.count):
        models.append(write_part(draw, args.out, i, args.seed, args.openscad_timeout))
        print("random_parts: %s %s, %d primitives" % (
            models[-1]["name"], models[-1]["source"].split(", ")[1],
            models[-1]["gt_primitives"]), file=sys.stderr)
    manifest = {"source": "scripts/random_parts.py --seed %d --count %d" % (
        args.seed, args.count), "models": models}
    with open(os.path.join(args.out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=2)
        f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
