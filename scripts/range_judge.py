"""Judging a range-image fit with nothing of the solver's: sensors, a renderer, voxels, metrics.

A result is judged as the sensor that took the input sees it: its OpenSCAD STL is rasterised
through the image's own sidecar camera (orthographic or pinhole, pixel centres at u + 0.5,
v + 0.5, depth along camera z, the formulas of ../shared/benchmarks/range/README.md) and the
depth map compared with the input's. Against the whole ground-truth solid it is judged by volume
IoU on one voxel grid (scripts/stl_voxelize.py's ray parity). Used by scripts/bench_range.py and
tests/python/test_range_judge.py; numpy, PIL and the standard library only.
"""

import json
import os
import re
import sys

import numpy as np
from PIL import Image

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import bench_3d  # noqa: E402  (its voxel grid and IoU: one definition of "inside" for both)
import stl_voxelize  # noqa: E402

read_stl = stl_voxelize.read_stl

# ----------------------------------------------------------------------------------------------
# The sensor


def load_camera(image_path):
    """The sidecar (same name, .json) of a range image as a dict with numpy matrices added:
    c2w and w2c (4 x 4). Raises ValueError when the camera is not one we can render through."""
    with open(os.path.splitext(image_path)[0] + ".json") as f:
        cam = json.load(f)
    c2w = np.array(cam["camera_to_world"], dtype=np.float64).reshape(4, 4)
    if cam["projection"] not in ("orthographic", "pinhole"):
        raise ValueError("%s: unknown projection %r" % (image_path, cam["projection"]))
    cam["c2w"], cam["w2c"] = c2w, np.linalg.inv(c2w)
    return cam


def read_depth(image_path, cam):
    """The image's depth (H x W float64, along camera z), NaN where the sensor had no return."""
    if image_path.endswith(".npy"):
        return np.load(image_path).astype(np.float64)
    raw = np.asarray(Image.open(image_path)).astype(np.float64)
    depth = raw * float(cam["depth_unit"])
    depth[raw == cam.get("no_return", 0)] = np.nan
    return depth


def to_camera(points, cam):
    """(..., 3) model-coordinate points in the camera frame (x right, y down, z forward)."""
    w2c = cam["w2c"]
    return points @ w2c[:3, :3].T + w2c[:3, 3]


def back_project(depth, cam):
    """(H, W, 3) model-coordinate points of a depth map (NaN where it has none): the README's
    pixel -> point formulas, so that the renderer below can be checked against them."""
    h, w = depth.shape
    u, v = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    if cam["projection"] == "orthographic":
        x = (u - cam["cx"]) * cam["pixel_size"]
        y = (v - cam["cy"]) * cam["pixel_size"]
    else:
        x = (u - cam["cx"]) / cam["fx"] * depth
        y = (v - cam["cy"]) / cam["fy"] * depth
    pc = np.stack([x, y, depth], axis=-1)
    c2w = cam["c2w"]
    return pc @ c2w[:3, :3].T + c2w[:3, 3]


def project(pc, cam):
    """Camera-frame points to (sx, sy, z): continuous pixel coordinates, pixel (u, v)'s centre
    at (u + 0.5, v + 0.5), and depth."""
    x, y, z = pc[..., 0], pc[..., 1], pc[..., 2]
    if cam["projection"] == "orthographic":
        return x / cam["pixel_size"] + cam["cx"], y / cam["pixel_size"] + cam["cy"], z
    with np.errstate(divide="ignore", invalid="ignore"):
        return cam["fx"] * x / z + cam["cx"], cam["fy"] * y / z + cam["cy"], z


# ----------------------------------------------------------------------------------------------
# The renderer: a z-buffer over triangle x pixel pairs, batched so memory stays bounded

PAIRS_PER_BATCH = 2_000_000


def _pixel_ranges(sx, sy, width, height):
    """Per triangle, the pixel columns u0..u1 and rows v0..v1 whose centres its box covers."""
    u0 = np.clip(np.ceil(sx.min(axis=1) - 0.5), 0, width).astype(np.int64)
    u1 = np.clip(np.floor(sx.max(axis=1) - 0.5), -1, width - 1).astype(np.int64)
    v0 = np.clip(np.ceil(sy.min(axis=1) - 0.5), 0, height).astype(np.int64)
    v1 = np.clip(np.floor(sy.max(axis=1) - 0.5), -1, height - 1).astype(np.int64)
    return u0, np.maximum(u1 - u0 + 1, 0), v0, np.maximum(v1 - v0 + 1, 0)


def _batches(counts):
    """Slices of triangle indices whose pixel pairs add up to about PAIRS_PER_BATCH each."""
    ends = np.cumsum(counts)
    start = 0
    while start < len(counts):
        base = ends[start - 1] if start else 0
        stop = int(np.searchsorted(ends, base + PAIRS_PER_BATCH, side="right"))
        stop = max(stop, start + 1)
        yield slice(start, stop)
        start = stop


def _raster_batch(sx, sy, inv_z, u0, nu, v0, nv, width):
    """(pixel index, 1/z or z) of every pixel centre inside a triangle of the batch."""
    counts = nu * nv
    tri = np.repeat(np.arange(len(counts)), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    px = u0[tri] + local % nu[tri] + 0.5
    py = v0[tri] + local // nu[tri] + 0.5
    x, y = sx[tri], sy[tri]
    area = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    w1 = ((px - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (py - y[:, 0])) / area
    w2 = ((x[:, 1] - x[:, 0]) * (py - y[:, 0]) - (px - x[:, 0]) * (y[:, 1] - y[:, 0])) / area
    w0 = 1.0 - w1 - w2
    # A hair of slack so that no pixel centre falls through the crack between two triangles;
    # a centre counted twice is harmless, the z-buffer keeps the nearer.
    tol = -1e-9
    inside = (w0 >= tol) & (w1 >= tol) & (w2 >= tol)
    val = (w0 * inv_z[tri, 0] + w1 * inv_z[tri, 1] + w2 * inv_z[tri, 2])[inside]
    pix = (py[inside] - 0.5).astype(np.int64) * width + (px[inside] - 0.5).astype(np.int64)
    return pix, val


def render_depth(tris, cam):
    """Depth along camera z of the mesh `tris` ((n, 3, 3), model coordinates) as the sidecar's
    sensor sees it: (H, W), NaN where no triangle is hit. Pinhole depth is interpolated as 1/z,
    which is linear in the image, so a slanted face is exact and not merely close."""
    width, height = int(cam["width"]), int(cam["height"])
    sx, sy, z = project(to_camera(tris, cam), cam)
    pinhole = cam["projection"] == "pinhole"
    keep = np.all(z > 1e-9, axis=1) if pinhole else np.ones(len(tris), bool)
    sx, sy, z = sx[keep], sy[keep], z[keep]
    area = ((sx[:, 1] - sx[:, 0]) * (sy[:, 2] - sy[:, 0])
            - (sx[:, 2] - sx[:, 0]) * (sy[:, 1] - sy[:, 0]))
    edge_on = np.abs(area) < 1e-12  # seen edge-on: covers no pixel centre
    sx, sy, z = sx[~edge_on], sy[~edge_on], z[~edge_on]
    val = 1.0 / z if pinhole else z
    u0, nu, v0, nv = _pixel_ranges(sx, sy, width, height)
    nearest = np.full(width * height, np.inf)
    for b in _batches(nu * nv):
        pix, vb = _raster_batch(sx[b], sy[b], val[b], u0[b], nu[b], v0[b], nv[b], width)
        depth = 1.0 / vb if pinhole else vb
        np.minimum.at(nearest, pix, depth)
    nearest[~np.isfinite(nearest)] = np.nan
    return nearest.reshape(height, width)


# ----------------------------------------------------------------------------------------------
# Metrics


def bbox_diagonal(tris):
    """Length of the diagonal of the mesh's axis-aligned bounding box."""
    pts = tris.reshape(-1, 3)
    return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def view_metrics(input_depth, result_depth, diagonal):
    """Silhouette IoU (input returns vs result hits) and the depth error over the pixels both
    have, as % of `diagonal`: mean, median and 95th percentile of |result - input|."""
    seen, hit = np.isfinite(input_depth), np.isfinite(result_depth)
    union = np.count_nonzero(seen | hit)
    both = seen & hit
    out = {"silhouette_iou": 1.0 if union == 0 else np.count_nonzero(seen & hit) / union,
           "input_returns": int(np.count_nonzero(seen)), "result_hits": int(np.count_nonzero(hit)),
           "both": int(np.count_nonzero(both))}
    if out["both"]:
        err = np.abs(result_depth[both] - input_depth[both]) / diagonal * 100.0
        out.update(depth_err_pct=float(err.mean()), depth_err_median_pct=float(np.median(err)),
                   depth_err_p95_pct=float(np.percentile(err, 95)))
    return out


def volume_iou(tris_a, tris_b, grid=128):
    """|A & B| / |A | B| of two closed meshes voxelised on one common grid of at least grid^3
    cubic voxels over the union of their boxes (the 3D benchmark's grid and voxeliser)."""
    return bench_3d.volume_iou(tris_a, tris_b, grid)[0]


# The 3D primitives of OpenSCAD's flattened .csg; circle/square/polygon only ever appear inside
# an extrusion there, which is itself counted once.
CSG_PRIMITIVE_RE = re.compile(r"\b(cube|sphere|cylinder|polyhedron|rotate_extrude|"
                              r"linear_extrude|surface)\s*\(")


def count_primitives(csg_text):
    """Primitive calls in a flattened .csg (modules and loops already expanded by OpenSCAD)."""
    return len(CSG_PRIMITIVE_RE.findall(csg_text))


# ----------------------------------------------------------------------------------------------
# Pictures


def _grey(depth, lo, hi):
    """Near = bright, no return = black."""
    img = np.zeros(depth.shape, np.uint8)
    ok = np.isfinite(depth)
    img[ok] = (255 - 200 * np.clip((depth[ok] - lo) / max(hi - lo, 1e-12), 0, 1)).astype(np.uint8)
    return np.stack([img] * 3, axis=-1)


def _error_rgb(input_depth, result_depth, diagonal, full_scale_pct=1.0):
    """Red = result too far, blue = too near (full at `full_scale_pct` of the diagonal); yellow
    where only the input has a return, green where only the result has one."""
    seen, hit = np.isfinite(input_depth), np.isfinite(result_depth)
    rgb = np.zeros(input_depth.shape + (3,), np.uint8)
    both = seen & hit
    err = np.zeros(input_depth.shape)
    err[both] = (result_depth[both] - input_depth[both]) / diagonal * 100.0 / full_scale_pct
    mag = (np.clip(np.abs(err), 0, 1) * 255).astype(np.uint8)
    rgb[both & (err > 0), 0] = mag[both & (err > 0)]
    rgb[both & (err <= 0), 2] = mag[both & (err <= 0)]
    rgb[both & (mag < 20)] = 40
    rgb[seen & ~hit] = (230, 200, 0)
    rgb[hit & ~seen] = (0, 190, 0)
    return rgb


def save_strip(path, input_depth, result_depth, diagonal):
    """input depth | result depth | error, side by side, one PNG."""
    finite = np.concatenate([d[np.isfinite(d)] for d in (input_depth, result_depth)])
    lo, hi = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    gap = np.full((input_depth.shape[0], 4, 3), 255, np.uint8)
    strip = np.concatenate([_grey(input_depth, lo, hi), gap, _grey(result_depth, lo, hi), gap,
                            _error_rgb(input_depth, result_depth, diagonal)], axis=1)
    Image.fromarray(strip).save(path, optimize=True)


# ----------------------------------------------------------------------------------------------
# object_b: the seed's precedence graph (Lin & Chen, Fig. 10 and its primitive table)

TOLERANCE = 0.05
BLOCK_KINDS = ("box", "block", "cube", "cuboid")


def find_graph(doc):
    """The "precedence_graph" object wherever it stands in the solver's JSON, or None."""
    if isinstance(doc, dict):
        if isinstance(doc.get("precedence_graph"), dict):
            return doc["precedence_graph"]
        children = doc.values()
    elif isinstance(doc, list):
        children = doc
    else:
        return None
    for child in children:
        found = find_graph(child)
        if found is not None:
            return found
    return None


def _number(value):
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def cylinder_size(node):
    """(radius, altitude) of a cylinder node, each None when the node does not say: named keys
    first (radius / r, height / h / altitude / length), else dims as Primitive3D keeps them,
    [r, r, height], or as [radius, altitude]."""
    dims = node.get("dims")
    named = dict(node, **dims) if isinstance(dims, dict) else node
    r = next((_number(named[k]) for k in ("radius", "r") if k in named), None)
    h = next((_number(named[k]) for k in ("height", "h", "altitude", "length") if k in named),
             None)
    if isinstance(dims, (list, tuple)) and dims:
        r = r if r is not None else _number(dims[0])
        h = h if h is not None or len(dims) < 2 else _number(dims[2 if len(dims) > 2 else 1])
    return r, h


def block_size(node):
    """The block's three edge lengths, sorted, or None."""
    dims = node.get("dims")
    if isinstance(dims, dict):
        dims = [dims.get(k) for k in ("x", "y", "z")]
    if not isinstance(dims, (list, tuple)) or len(dims) < 3:
        return None
    vals = [_number(d) for d in dims[:3]]
    return None if None in vals else sorted(abs(v) for v in vals)


def _near(value, target):
    return value is not None and abs(value - target) <= TOLERANCE * target


def _identify(nodes):
    """The object_b roles among the nodes: block, big, small (list), top; None where missing.
    Cylinders are told apart by radius alone, so that a wrong order or sign is still reported
    against the right primitive."""
    kind = lambda n: str(n.get("kind", "")).lower()
    blocks = [n for n in nodes if kind(n) in BLOCK_KINDS]
    cyls = [n for n in nodes if kind(n) == "cylinder" and cylinder_size(n)[0] is not None]
    block = max(blocks, key=lambda n: np.prod(block_size(n) or [0])) if blocks else None
    cyls = sorted(cyls, key=lambda n: -cylinder_size(n)[0])
    big = cyls[0] if cyls else None
    rest = cyls[1:]
    top = min(rest, key=lambda n: abs(cylinder_size(n)[0] - 0.75)) if rest else None
    small = sorted([n for n in rest if n is not top],
                   key=lambda n: abs(cylinder_size(n)[0] - 0.5))[:2]
    return block, big, small, top


def _field_check(node, key, want):
    """(ok, detail) of node[key] == want; ok None (not available) when either is missing."""
    if node is None:
        return None, "primitive not found"
    if key not in node:
        return None, "%s not available" % key
    got = node[key]
    if isinstance(want, str):
        return str(got).lower() == want, "%s %s" % (key, got)
    return _number(got) == want, "%s %s" % (key, got)


def _all(checks):
    """One (ok, detail) of several: False if any is False, None if any is unknown."""
    oks = [c[0] for c in checks]
    ok = False if False in oks else (None if None in oks else True)
    return ok, "; ".join(c[1] for c in checks)


def object_b_checks(doc):
    """[(item, ok, detail)] for the solver's JSON of object_b's range image; ok is None where
    the JSON does not say (a missing key is "not available", never a crash)."""
    graph = find_graph(doc) if doc is not None else None
    nodes = graph.get("nodes") if isinstance(graph, dict) else None
    if not isinstance(nodes, list) or not nodes:
        return [("precedence graph", None, "not available in the JSON")]
    nodes = [n for n in nodes if isinstance(n, dict)]
    block, big, small, top = _identify(nodes)
    out = [("block order 1", *_field_check(block, "order", 1)),
           ("large cylinder order 2, negative",
            *_all([_field_check(big, "order", 2), _field_check(big, "sign", "negative")])),
           ("two small cylinders order 3, positive",
            *_all([c for n in small for c in (_field_check(n, "order", 3),
                                               _field_check(n, "sign", "positive"))]
                  or [(False, "fewer than two small cylinders")]))]
    out.append(("top cylinder its own subobject", *_own_subobject(top, nodes)))
    out += _size_checks(block, big, small, top)
    arcs = graph.get("arcs")
    out.append(("arcs (information)", None, "not available" if not isinstance(arcs, list) else
                ", ".join("%s->%s %s" % (a.get("from"), a.get("to"), a.get("kind"))
                          for a in arcs if isinstance(a, dict)) or "none"))
    return out


def _own_subobject(top, nodes):
    if top is None:
        return None, "primitive not found"
    if "subobject" not in top:
        return None, "subobject not available"
    mates = [n for n in nodes if n is not top and n.get("subobject") == top["subobject"]]
    return not mates, "subobject %s shared with %d other(s)" % (top["subobject"], len(mates))


def _size_checks(block, big, small, top):
    """The paper's table within 5 %: block 3.0 x 1.5 x 3.0, radii 2.5 / 0.5 / 0.5 / 0.75,
    altitudes 1.5 / 1.75 / 1.75 / 0.75. The large cylinder is seen only where it cuts the
    block, so any altitude that spans the block's 1.5 is right."""
    out = []
    dims = block_size(block) if block is not None else None
    out.append(("block 1.5 x 3.0 x 3.0", None if dims is None else
                all(_near(d, t) for d, t in zip(dims, (1.5, 3.0, 3.0))),
                "dims %s" % (["%.3f" % d for d in dims] if dims else "not available")))
    want = [("large cylinder r 2.5, altitude >= 1.5", big, 2.5, None),
            ("small cylinder r 0.5, altitude 1.75", small[0] if small else None, 0.5, 1.75),
            ("small cylinder r 0.5, altitude 1.75", small[1] if len(small) > 1 else None,
             0.5, 1.75),
            ("top cylinder r 0.75, altitude 0.75", top, 0.75, 0.75)]
    for item, node, r_want, h_want in want:
        if node is None:
            out.append((item, None, "primitive not found"))
            continue
        r, h = cylinder_size(node)
        h_ok = (h is not None and h >= 1.5 * (1 - TOLERANCE)) if h_want is None \
            else _near(h, h_want)
        ok = None if r is None or h is None else (_near(r, r_want) and h_ok)
        out.append((item, ok, "r %s, altitude %s" % tuple(
            "n/a" if v is None else "%.3f" % v for v in (r, h))))
    return out
