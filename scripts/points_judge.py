"""Judging a point-cloud fit (csgfit points) with nothing of the solver's: B-splines, patches, STEP.

The blade of ../shared/benchmarks/points is judged by its surface: the true B-spline patch
(blade.gt.json) and the fitted one (the result's nurbs leaf, the format of issue 14's contract)
are evaluated here, by our own Cox-de Boor recursion, and compared along vertical lines, the
seed's 2.5D measure. The result's STEP is opened in FreeCAD (a freecadcmd script written to a
temporary file), its .scad rendered by OpenSCAD and seen from above by range_judge's renderer.

A patch is evaluated as OpenCASCADE does: every coordinate of a point is the B-spline of the
control points' coordinates, P(u, v) = sum N_i(u) N_j(v) P_ij. With the control points at the
Greville abscissae (the contract) that is the contract's height field z = S(x, y); the ground
truth's control points are not there (its x are 60 i / 14), and its scans were sampled from
this parametric surface, so only this reading judges both. Used by scripts/bench_points.py and
tests/python/test_points_judge.py; numpy and the standard library only.
"""

import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import range_judge as rj  # noqa: E402  (its z-buffer sees the .scad from above)

# ----------------------------------------------------------------------------------------------
# B-splines


def basis(knots, degree, t):
    """(len(t), n) values of the n = len(knots) - degree - 1 B-spline basis functions at the
    parameters t, by Cox-de Boor. Spans are half open, [t_k, t_k+1), except that the last knot
    belongs to the last non-empty span, so that a clamped curve ends at its last control point."""
    kn = np.asarray(knots, dtype=np.float64)
    t = np.atleast_1d(np.asarray(t, dtype=np.float64))
    m = len(kn) - 1
    n = ((kn[:-1] <= t[:, None]) & (t[:, None] < kn[1:])).astype(np.float64)
    at_end = t >= kn[-1]
    n[at_end] = 0.0
    n[at_end, np.nonzero(kn[:-1] < kn[1:])[0][-1]] = 1.0
    for d in range(1, degree + 1):
        lo, hi = kn[:m - d], kn[d:m]            # support of N_{k, d-1}: [t_k, t_k+d]
        lo1, hi1 = kn[1:m - d + 1], kn[d + 1:m + 1]  # of N_{k+1, d-1}: [t_k+1, t_k+d+1]
        left = np.where(hi > lo, (t[:, None] - lo) / np.where(hi > lo, hi - lo, 1.0), 0.0)
        right = np.where(hi1 > lo1, (hi1 - t[:, None]) / np.where(hi1 > lo1, hi1 - lo1, 1.0), 0.0)
        n = left * n[:, :m - d] + right * n[:, 1:m - d + 1]
    return n


def basis_derivative(knots, degree, t):
    """dN/dt of the same functions: N'_k = d/(t_k+d - t_k) N_{k,d-1} - d/(t_k+d+1 - t_k+1)
    N_{k+1,d-1}, from the basis of one degree less on the same knots."""
    kn = np.asarray(knots, dtype=np.float64)
    low = basis(kn, degree - 1, t)  # n + 1 functions
    n = len(kn) - degree - 1
    a = kn[degree:degree + n] - kn[:n]
    b = kn[degree + 1:degree + 1 + n] - kn[1:n + 1]
    fa = np.where(a > 0, degree / np.where(a > 0, a, 1.0), 0.0)
    fb = np.where(b > 0, degree / np.where(b > 0, b, 1.0), 0.0)
    return fa * low[:, :n] - fb * low[:, 1:n + 1]


class Patch:
    """A tensor-product B-spline patch placed in the model: degrees (p, q), knots along u and
    v, the control net (nu, nv, 3) in local coordinates (index [i, j], i along u), and the
    frame: model = center + rotation @ local."""

    def __init__(self, degree, knots_u, knots_v, net, center=(0, 0, 0), rotation=np.eye(3)):
        self.degree = (int(degree[0]), int(degree[1]))
        self.knots_u = np.asarray(knots_u, dtype=np.float64)
        self.knots_v = np.asarray(knots_v, dtype=np.float64)
        self.net = np.asarray(net, dtype=np.float64)
        self.center = np.asarray(center, dtype=np.float64)
        self.rotation = np.asarray(rotation, dtype=np.float64)
        nu, nv = self.net.shape[:2]
        if (len(self.knots_u) != nu + self.degree[0] + 1
                or len(self.knots_v) != nv + self.degree[1] + 1 or self.net.shape[2] != 3):
            raise ValueError("nurbs: %d x %d control points do not fit %d + %d knots of degree "
                             "%s" % (nu, nv, len(self.knots_u), len(self.knots_v), self.degree))

    def _along_u(self, bu):
        """The net summed along u with the weights bu: (samples, nv, 3)."""
        nu, nv = self.net.shape[:2]
        # One matrix product, then the sum along v: einsum over three operands is ten times
        # slower on the benchmark's hundred thousand pixels.
        return (bu @ self.net.reshape(nu, nv * 3)).reshape(-1, nv, 3)

    def local(self, u, v):
        """Local points at paired (u, v)."""
        bu = basis(self.knots_u, self.degree[0], u)
        bv = basis(self.knots_v, self.degree[1], v)
        return np.sum(self._along_u(bu) * bv[:, :, None], axis=1)

    def frame(self, u, v):
        """Model points at paired (u, v) and their partial derivatives along u and v, the
        bases computed once for the three."""
        bu, dbu = (f(self.knots_u, self.degree[0], u) for f in (basis, basis_derivative))
        bv, dbv = (f(self.knots_v, self.degree[1], v) for f in (basis, basis_derivative))
        su, dsu = self._along_u(bu), self._along_u(dbu)
        point = np.sum(su * bv[:, :, None], axis=1)
        d_u = np.sum(dsu * bv[:, :, None], axis=1)
        d_v = np.sum(su * dbv[:, :, None], axis=1)
        rt = self.rotation.T
        return self.center + point @ rt, d_u @ rt, d_v @ rt

    def model(self, u, v):
        """Model points at paired (u, v)."""
        return self.center + self.local(u, v) @ self.rotation.T

    def grid(self, nu, nv):
        """Local points on an nu x nv grid of uniform (u, v), index [i, j] (i along u)."""
        bu = basis(self.knots_u, self.degree[0], np.linspace(0, 1, nu))
        bv = basis(self.knots_v, self.degree[1], np.linspace(0, 1, nv))
        return np.einsum("ai,ijc,bj->abc", bu, self.net, bv)


# ----------------------------------------------------------------------------------------------
# Readers and writers of patches


def quaternion_matrix(q):
    """The rotation (local -> model) of a quaternion [w, x, y, z], normalised first."""
    w, x, y, z = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def euler_matrix(deg):
    """OpenSCAD's rotate([a, b, c]): about x by a, then y by b, then z by c."""
    a, b, c = np.radians(np.asarray(deg, dtype=np.float64))
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def patch_from_gt(doc):
    """The true patch of blade.gt.json: model coordinates, control_points[i][j] = [x, y, z]."""
    return Patch((doc["degree_u"], doc["degree_v"]), doc["knots_u"], doc["knots_v"],
                 doc["control_points"])


def patch_from_leaf(leaf):
    """A result's nurbs leaf (the contract): the flat control points, u index fastest
    (P_ij = cp[i + nu * j]), in the frame of its center and rotation (euler_deg when the
    quaternion is missing)."""
    nu, nv = (int(c) for c in leaf["counts"])
    cp = np.asarray(leaf["control_points"], dtype=np.float64)
    if cp.shape != (nu * nv, 3):
        raise ValueError("nurbs: %s control points, counts say %d x %d" % (cp.shape, nu, nv))
    rot = (quaternion_matrix(leaf["rotation"]) if "rotation" in leaf
           else euler_matrix(leaf.get("euler_deg", (0, 0, 0))))
    return Patch(leaf["degree"], leaf["knots_u"], leaf["knots_v"],
                 cp.reshape(nv, nu, 3).transpose(1, 0, 2), leaf["center"], rot)


def nurbs_leaves(doc):
    """Every {"type": "nurbs"} object wherever it stands in a result's JSON."""
    if isinstance(doc, dict):
        if doc.get("type") == "nurbs":
            return [doc]
        children = doc.values()
    elif isinstance(doc, list):
        children = doc
    else:
        return []
    return [leaf for child in children for leaf in nurbs_leaves(child)]


def leaf_from_patch(patch, quaternion=(1.0, 0.0, 0.0, 0.0)):
    """The contract's JSON leaf of a patch whose rotation is `quaternion`."""
    net = patch.net
    nu, nv = net.shape[:2]
    size = [float(np.ptp(net[..., 0])), float(np.ptp(net[..., 1])), float(net[..., 2].max())]
    leaf = {"type": "nurbs", "center": patch.center.tolist(), "rotation": list(quaternion),
            "size": size, "degree": list(patch.degree), "counts": [nu, nv],
            "knots_u": patch.knots_u.tolist(), "knots_v": patch.knots_v.tolist(),
            "control_points": net.transpose(1, 0, 2).reshape(-1, 3).tolist()}
    if tuple(quaternion) == (1.0, 0.0, 0.0, 0.0):
        leaf["euler_deg"] = [0.0, 0.0, 0.0]  # for people; readers take the quaternion
    return leaf


GT_CHANGES = {"exact": (1.0, 0.0), "shifted": (1.0, 0.05), "scaled": (1.01, 0.0)}


def gt_as_leaf(gt_doc, how):
    """The ground truth as a result leaf (the contract's example: centred on its rectangle,
    identity rotation), its heights unchanged, raised by 0.05 mm or scaled by 1.01."""
    gt = patch_from_gt(gt_doc)
    net = gt.net.copy()
    center = np.array([(net[..., 0].min() + net[..., 0].max()) / 2,
                       (net[..., 1].min() + net[..., 1].max()) / 2, 0.0])
    scale, lift = GT_CHANGES[how]
    net -= center
    net[..., 2] = net[..., 2] * scale + lift
    return leaf_from_patch(Patch(gt.degree, gt.knots_u, gt.knots_v, net, center))


def result_document(leaf, source):
    """A 3D document whose tree is the one leaf."""
    return {"schema": "csgfit/1", "dimension": 3, "units": "mm", "source": source,
            "tree": leaf}


# ----------------------------------------------------------------------------------------------
# The surface along vertical lines


def heights(patch, x, y, iterations=60):
    """Where the vertical lines through (x, y) (model) meet the patch, by Newton on (u, v)
    clamped to [0, 1]: (z, hit, gap), gap the horizontal distance from each line to the point
    found (0 where it hits; a line beside the patch ends at the nearest edge point)."""
    x, y = np.ravel(x).astype(np.float64), np.ravel(y).astype(np.float64)
    rot, c = patch.rotation, patch.center
    net = patch.net
    lo, hi = net.reshape(-1, 3).min(axis=0), net.reshape(-1, 3).max(axis=0)
    # Start from the line's point at mid height, taken to local coordinates and mapped to (u, v)
    # as if the net were the rectangle it spans.
    mid = c + rot @ np.array([0, 0, (lo[2] + hi[2]) / 2])
    start = (np.stack([x, y, np.full_like(x, mid[2])], axis=1) - c) @ rot
    span = np.maximum(hi - lo, 1e-12)
    u = np.clip((start[:, 0] - lo[0]) / span[0], 0, 1)
    v = np.clip((start[:, 1] - lo[1]) / span[1], 0, 1)
    tol = 1e-10 * float(np.max(span))
    for _ in range(iterations):
        p, ju, jv = patch.frame(u, v)
        f = p[:, :2] - np.stack([x, y], axis=1)
        if np.all(np.abs(f) < tol):
            break
        det = ju[:, 0] * jv[:, 1] - ju[:, 1] * jv[:, 0]
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        u = np.clip(u - (f[:, 0] * jv[:, 1] - f[:, 1] * jv[:, 0]) / det, 0, 1)
        v = np.clip(v - (ju[:, 0] * f[:, 1] - ju[:, 1] * f[:, 0]) / det, 0, 1)
    else:
        p = patch.model(u, v)
    gap = np.hypot(p[:, 0] - x, p[:, 1] - y)
    return p[:, 2], gap < 1e-6 * float(np.max(span)) + tol, gap


def sample_grid(gt, samples=(200, 60)):
    """Cell centres of a samples[0] x samples[1] grid over the true patch's x-y rectangle
    (centres, so that no sample stands on the rectangle's very edge): (x, y) flat arrays."""
    lo, hi = gt.net.reshape(-1, 3).min(axis=0), gt.net.reshape(-1, 3).max(axis=0)
    xs = lo[0] + (np.arange(samples[0]) + 0.5) * (hi[0] - lo[0]) / samples[0]
    ys = lo[1] + (np.arange(samples[1]) + 0.5) * (hi[1] - lo[1]) / samples[1]
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    return gx.ravel(), gy.ravel()


def deviation(gt, fits, samples=(200, 60)):
    """How far the true surface is from the fitted patches along z, in model units: mean, max,
    p95 over the samples, the samples no patch lies above or below (`outside`; counted at their
    distance to the nearest patch edge point) and the true volume under the surface."""
    x, y = sample_grid(gt, samples)
    z_true, hit, _ = heights(gt, x, y)
    if not np.all(hit):
        raise ValueError("the true patch is not a height field over its rectangle")
    best = np.full(len(x), np.inf)
    beside = np.full(len(x), np.inf)
    for fit in fits:
        z, on, gap = heights(fit, x, y)
        dz = np.abs(z - z_true)
        best = np.where(on, np.minimum(best, dz), best)
        beside = np.minimum(beside, np.hypot(dz, gap))
    outside = ~np.isfinite(best)
    dev = np.where(outside, beside, best)
    lo, hi = gt.net.reshape(-1, 3).min(axis=0), gt.net.reshape(-1, 3).max(axis=0)
    return {"dev_mean": float(dev.mean()), "dev_max": float(dev.max()),
            "dev_p95": float(np.percentile(dev, 95)), "outside": int(outside.sum()),
            "samples": int(len(x)),
            "true_volume": float(z_true.mean() * (hi[0] - lo[0]) * (hi[1] - lo[1]))}


# ----------------------------------------------------------------------------------------------
# The patch as an OpenSCAD polyhedron (the --gt-as-result stand-in for the solver's .scad)

HEADER_RE = re.compile(r"//\s*(nurbs_\d+):\s*polyhedron of (\d+)\s*x\s*(\d+) cells, deviation "
                       r"<=\s*([0-9.eE+-]+)\s*mm")


def header_deviations(text):
    """{leaf name: reported deviation} from a .scad's header lines."""
    return {m.group(1): float(m.group(4)) for m in HEADER_RE.finditer(text)}


def _polyhedron_faces(a, b):
    """Triangles of the solid under an (a + 1) x (b + 1) grid: top vertices k = i + (a + 1) j,
    the floor's k + (a + 1)(b + 1); outward normals by the right-hand rule."""
    w, n = a + 1, (a + 1) * (b + 1)
    tris = []
    for j in range(b):
        for i in range(a):
            p, q, r, s = i + w * j, i + 1 + w * j, i + 1 + w * (j + 1), i + w * (j + 1)
            tris += [(p, q, r), (p, r, s), (n + p, n + r, n + q), (n + p, n + s, n + r)]
    ring = ([i for i in range(a)] + [a + w * j for j in range(b)]
            + [i + w * b for i in range(a, 0, -1)] + [w * j for j in range(b, 0, -1)])
    for p, q in zip(ring, ring[1:] + ring[:1]):  # counter-clockwise seen from above
        tris += [(n + p, n + q, q), (n + p, q, p)]
    return tris


def polyhedron_scad(patch, name="nurbs_1", cells=(240, 80)):
    """The solid under the patch as a .scad: a polyhedron in the leaf's multmatrix, with the
    contract's header line. The deviation written is the largest gap between the exact patch
    and the triangles at the cells' centres (the midpoints of the diagonals)."""
    a, b = cells
    top = patch.grid(a + 1, b + 1)
    centre = patch.grid(2 * a + 1, 2 * b + 1)[1::2, 1::2]
    dev = float(np.linalg.norm(centre - (top[:-1, :-1] + top[1:, 1:]) / 2, axis=2).max())
    top = top.transpose(1, 0, 2).reshape(-1, 3)  # index i + (a + 1) j
    floor = top * np.array([1.0, 1.0, 0.0])
    points = np.concatenate([top, floor])
    # OpenSCAD wants each face clockwise seen from outside: the outward triangles reversed.
    faces = [(r, q, p) for p, q, r in _polyhedron_faces(a, b)]
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = patch.rotation, patch.center
    return ("// %s: polyhedron of %dx%d cells, deviation <= %.3g mm from the exact B-spline "
            "patch\nmultmatrix(%s)\npolyhedron(points=%s,\nfaces=%s);\n" % (
                name, a, b, dev, json.dumps(m.tolist()),
                json.dumps(np.round(points, 9).tolist()), json.dumps(faces)))


def top_deviation(tris, gt, pixel=0.2, inset=2):
    """The rendered solid (an STL's triangles) seen from straight above by range_judge's
    orthographic z-buffer over the true rectangle, against the true surface: mean and max
    |z| difference over the pixels `inset` or more pixels inside the rectangle's edges."""
    lo, hi = gt.net.reshape(-1, 3).min(axis=0), gt.net.reshape(-1, 3).max(axis=0)
    ztop = max(hi[2], tris[..., 2].max()) + 1.0
    c2w = np.array([[1, 0, 0, lo[0]], [0, -1, 0, hi[1]], [0, 0, -1, ztop], [0, 0, 0, 1]], float)
    cam = {"projection": "orthographic", "width": int(round((hi[0] - lo[0]) / pixel)),
           "height": int(round((hi[1] - lo[1]) / pixel)), "cx": 0.0, "cy": 0.0,
           "pixel_size": pixel, "c2w": c2w, "w2c": np.linalg.inv(c2w)}
    depth = rj.render_depth(tris, cam)[inset:-inset, inset:-inset]
    seen = rj.back_project(np.pad(depth, inset, constant_values=np.nan), cam)
    seen = seen[inset:-inset, inset:-inset][np.isfinite(depth)]
    if not len(seen):
        raise ValueError("the .scad's solid is nowhere above the true rectangle")
    z_true, _, _ = heights(gt, seen[:, 0], seen[:, 1])
    dz = np.abs(seen[:, 2] - z_true)
    return {"scad_top_dev_mean": float(dz.mean()), "scad_top_dev_max": float(dz.max()),
            "scad_top_coverage": float(np.isfinite(depth).mean())}


# ----------------------------------------------------------------------------------------------
# FreeCAD: the STEP check, and the stand-in STEP of --gt-as-result

FREECAD_MARK = "POINTSJUDGE "

STEP_CHECK = r'''
import json, os, traceback
try:
    import Mesh, Part
    shape = Part.read(os.environ["POINTSJUDGE_STEP"])
    solids = shape.Solids
    out = {"solids": len(solids), "faces": len(shape.Faces),
           "valid": bool(shape.isValid()) and all(s.isValid() for s in solids),
           "bspline_face": any(isinstance(f.Surface, Part.BSplineSurface) for f in shape.Faces),
           "volume": float(shape.Volume),
           # OCCT's own volume of a B-spline solid can be off by tenths of a percent (swept
           # walls); the volume of a fine tessellation is the one to compare.
           "mesh_volume": float(Mesh.Mesh(shape.tessellate(0.005)).Volume)}
except Exception:
    out = {"error": traceback.format_exc().strip().splitlines()[-1]}
print("%s" + json.dumps(out))
''' % FREECAD_MARK

# The solid of one nurbs leaf: the exact face extruded down past the local floor, cut there by a
# box, placed by the leaf's frame (FreeCAD's Rotation takes the quaternion as x, y, z, w).
STEP_WRITE = r'''
import json, os, traceback
try:
    import FreeCAD as App, Part
    leaf = json.load(open(os.environ["POINTSJUDGE_JSON"]))["tree"]
    (p, q), (nu, nv), cp = leaf["degree"], leaf["counts"], leaf["control_points"]
    poles = [[App.Vector(*cp[i + nu * j]) for j in range(nv)] for i in range(nu)]
    def distinct(knots):
        ks = sorted(set(knots))
        return ks, [knots.count(k) for k in ks]
    (ku, mu), (kv, mv) = distinct(leaf["knots_u"]), distinct(leaf["knots_v"])
    surf = Part.BSplineSurface()
    surf.buildFromPolesMultsKnots(poles, mu, mv, ku, kv, False, False, p, q)
    top = max(c[2] for c in cp) + 1.0
    prism = surf.toShape().extrude(App.Vector(0, 0, -2 * top))
    big = 4 * max(abs(c[k]) for c in cp for k in (0, 1)) + 1.0
    solid = prism.common(Part.makeBox(big, big, 2 * top, App.Vector(-big / 2, -big / 2, 0)))
    solid = solid.Solids[0]
    w, x, y, z = leaf["rotation"]
    solid.Placement = App.Placement(App.Vector(*leaf["center"]), App.Rotation(x, y, z, w))
    solid.exportStep(os.environ["POINTSJUDGE_STEP"])
    out = {"written": True}
except Exception:
    out = {"error": traceback.format_exc().strip().splitlines()[-1]}
print("%s" + json.dumps(out))
''' % FREECAD_MARK


def freecad(script, env, timeout=300.0, exe="freecadcmd"):
    """Runs `script` (text) in freecadcmd with `env` added; the dict its marked line prints.
    Raises RuntimeError when FreeCAD fails or the script reports an error."""
    with tempfile.NamedTemporaryFile("w", suffix=".py", delete=False) as f:
        f.write(script)
    try:
        proc = subprocess.run([exe, f.name], env=dict(os.environ, **env), capture_output=True,
                              text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise RuntimeError("freecadcmd did not finish within %g s" % timeout)
    finally:
        os.remove(f.name)
    lines = [l for l in proc.stdout.splitlines() if l.startswith(FREECAD_MARK)]
    if not lines:
        last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise RuntimeError("freecadcmd exit %d: %s" % (proc.returncode, last[:200]))
    out = json.loads(lines[-1][len(FREECAD_MARK):])
    if "error" in out:
        raise RuntimeError("FreeCAD: %s" % out["error"][:200])
    return out


def step_check(step, timeout=300.0):
    """FreeCAD's reading of a STEP: solids, faces, valid, bspline_face, volume, mesh_volume and
    passed (exactly one valid solid with a B-spline face)."""
    out = freecad(STEP_CHECK, {"POINTSJUDGE_STEP": os.path.abspath(step)}, timeout)
    out["passed"] = out["solids"] == 1 and out["valid"] and out["bspline_face"]
    return out


def write_step(result_json, step, timeout=300.0):
    """The STEP of a one-leaf result document, built by FreeCAD from its control net."""
    freecad(STEP_WRITE, {"POINTSJUDGE_JSON": os.path.abspath(result_json),
                         "POINTSJUDGE_STEP": os.path.abspath(step)}, timeout)
