#!/usr/bin/python3
"""End-to-end 2D benchmark: csgfit CLI -> .scad -> OpenSCAD rendering -> IoU, next to potrace.

For every bitmap of ../shared/benchmarks/2d (manifest.json) this runs
`csgfit image IN -o OUT.scad --time T`, renders OUT.scad with OpenSCAD (scripts/scad_raster.py),
scores the rendering against the input and against the solver's own raster, traces the same
bitmap with potrace for a side-by-side baseline, and writes a per-bitmap CSV plus a Markdown
table per category. What each column means is written down in docs/BENCHMARKS.md.

Runs on Debian's /usr/bin/python3 with numpy only (PIL is used to read PNGs when present).
A failure on one bitmap is recorded, never aborts the run; the exit status is 1 if any failed.
"""

import argparse
import concurrent.futures
import csv
import datetime
import json
import math
import os
import platform
import re
import shlex
import shutil
import statistics
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
import zlib

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(SCRIPT_DIR)
DEFAULT_BENCH_DIR = os.path.normpath(os.path.join(REPO_DIR, "..", "shared", "benchmarks", "2d"))
DOC_BEGIN = "<!-- bench2d:begin -->"
DOC_END = "<!-- bench2d:end -->"

# Display order and labels of the manifest's `kind` values.
CATEGORY_LABELS = {
    "glyph": "glyph (DejaVu letters)",
    "icon": "icon (Adwaita symbolic)",
    "synthetic": "part (random CSG, ground truth)",
    "topopt": "topopt (SIMP results)",
    "csgnet_cad": "csgnet_cad (CSGNet 2D CAD)",
}

# ----------------------------------------------------------------------------------------------
# PNG / PBM input and output (numpy + zlib, so the script needs no imaging library)


def _png_chunks(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG file")
    pos = 8
    while pos + 8 <= len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        yield kind, data[pos + 8:pos + 8 + length]
        pos += 12 + length


def _unfilter(raw, height, stride, bpp):
    out = np.zeros((height, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.int32)
    pos = 0
    for r in range(height):
        ftype = raw[pos]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=pos + 1).astype(np.int32)
        pos += 1 + stride
        if ftype == 0:
            cur = line
        elif ftype == 2:
            cur = (line + prev) & 0xFF
        else:  # Sub, Average, Paeth depend on the left neighbour: go byte by byte.
            cur = np.zeros(stride, dtype=np.int32)
            for i in range(stride):
                a = cur[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                if ftype == 1:
                    p = a
                elif ftype == 3:
                    p = (a + b) >> 1
                elif ftype == 4:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if (pa <= pb and pa <= pc) else (b if pb <= pc else c)
                else:
                    raise ValueError("bad PNG filter type %d" % ftype)
                cur[i] = (line[i] + p) & 0xFF
        out[r] = cur
        prev = cur
    return out


def read_png_grey(path):
    """Returns an H x W uint8 grey image (alpha composited on white)."""
    try:
        from PIL import Image  # optional; handles every PNG flavour
        with Image.open(path) as im:
            if im.mode in ("RGBA", "LA", "P"):
                im = im.convert("RGBA")
                bg = Image.new("RGBA", im.size, (255, 255, 255, 255))
                im = Image.alpha_composite(bg, im)
            return np.array(im.convert("L"), dtype=np.uint8)
    except ImportError:
        pass
    with open(path, "rb") as f:
        data = f.read()
    idat = b""
    for kind, body in _png_chunks(data):
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
    if depth != 8 or interlace or channels is None:
        raise ValueError("%s: only 8-bit non-interlaced grey/RGB(A) PNGs without PIL" % path)
    px = _unfilter(zlib.decompress(idat), h, w * channels, channels).reshape(h, w, channels)
    px = px.astype(np.float64)
    if channels in (2, 4):
        alpha = px[..., -1:] / 255.0
        px = px[..., :-1] * alpha + 255.0 * (1 - alpha)
    grey = px[..., 0] if px.shape[2] == 1 else px @ np.array([0.299, 0.587, 0.114])
    return np.clip(np.rint(grey), 0, 255).astype(np.uint8)


def write_png_rgb(path, rgb):
    """Writes an H x W x 3 uint8 array as an 8-bit RGB PNG."""
    rgb = np.ascontiguousarray(rgb, dtype=np.uint8)
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[r].tobytes() for r in range(h))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


def write_pbm(path, mask):
    """Writes a bool mask as binary PBM (P4): 1 = black = foreground, rows padded to bytes."""
    h, w = mask.shape
    with open(path, "wb") as f:
        f.write(b"P4\n%d %d\n" % (w, h))
        f.write(np.packbits(mask.astype(np.uint8), axis=1).tobytes())


def foreground_mask(grey, foreground="black"):
    """The bitmaps are clean black/white; the shape is the `foreground` colour."""
    return grey < 128 if foreground != "white" else grey >= 128


def iou(a, b):
    union = np.count_nonzero(a | b)
    return 1.0 if union == 0 else np.count_nonzero(a & b) / union


# ----------------------------------------------------------------------------------------------
# SVG paths (potrace output): parse, flatten Beziers, rasterise at pixel centres

NUMBER_RE = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
PATH_TOKEN_RE = re.compile(r"[MmLlHhVvCcSsQqZz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
PARAM_COUNT = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "Z": 0}


def _bezier_points(ctrl):
    """Flattens one Bezier (3 or 4 control points) into points after the first one."""
    ctrl = np.asarray(ctrl, dtype=np.float64)
    length = np.sum(np.hypot(*np.diff(ctrl, axis=0).T))
    n = int(min(256, max(8, math.ceil(length / 0.25))))  # <= 1/4 unit per chord
    t = np.linspace(0.0, 1.0, n + 1)[1:, None]
    if len(ctrl) == 3:
        p0, p1, p2 = ctrl
        return (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t ** 2 * p2
    p0, p1, p2, p3 = ctrl
    return ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
            + t ** 3 * p3)


def parse_svg_path(d):
    """Path data -> list of closed polylines (N x 2 arrays, path coordinates).

    Handles absolute and relative M L H V C S Q Z with implicit repetition, which covers what
    potrace writes (M, l, c, m, z)."""
    tokens = PATH_TOKEN_RE.findall(d)
    polys, cur = [], []
    x = y = 0.0
    start = (0.0, 0.0)
    last_ctrl = None
    cmd = None
    i = 0

    def close():
        nonlocal cur
        if len(cur) >= 3:
            polys.append(np.array(cur, dtype=np.float64))
        cur = []

    while i < len(tokens):
        tok = tokens[i]
        if tok.isalpha():
            cmd = tok
            i += 1
            if cmd in "Zz":
                close()
                x, y = start
                last_ctrl = None
                continue
        elif cmd is None:
            raise ValueError("path data starts with a number")
        n = PARAM_COUNT[cmd.upper()]
        args = [float(t) for t in tokens[i:i + n]]
        if len(args) < n:
            raise ValueError("truncated path data")
        i += n
        rel = cmd.islower()
        up = cmd.upper()
        if up == "M":
            close()
            x, y = (x + args[0], y + args[1]) if rel else (args[0], args[1])
            start = (x, y)
            cur = [(x, y)]
            cmd = "l" if rel else "L"  # implicit repetition after a moveto is a lineto
            last_ctrl = None
            continue
        if not cur:
            cur = [(x, y)]
        if up in "LHV":
            if up == "L":
                nx, ny = (x + args[0], y + args[1]) if rel else (args[0], args[1])
            elif up == "H":
                nx, ny = (x + args[0] if rel else args[0]), y
            else:
                nx, ny = x, (y + args[0] if rel else args[0])
            cur.append((nx, ny))
            x, y = nx, ny
            last_ctrl = None
        else:
            pts = [(args[k] + (x if rel else 0), args[k + 1] + (y if rel else 0))
                   for k in range(0, n, 2)]
            if up == "S":
                refl = (2 * x - last_ctrl[0], 2 * y - last_ctrl[1]) if last_ctrl else (x, y)
                pts = [refl] + pts
            ctrl = [(x, y)] + pts
            if up == "Q":
                ctrl = ctrl[:3]
            cur.extend(map(tuple, _bezier_points(ctrl)))
            last_ctrl = ctrl[-2]
            x, y = ctrl[-1]
    close()
    return polys


def _parse_transform(text):
    """SVG transform attribute -> 3 x 3 matrix (translate, scale, matrix)."""
    m = np.eye(3)
    for name, body in re.findall(r"(\w+)\s*\(([^)]*)\)", text or ""):
        v = [float(t) for t in NUMBER_RE.findall(body)]
        t = np.eye(3)
        if name == "translate":
            t[0, 2], t[1, 2] = v[0], (v[1] if len(v) > 1 else 0.0)
        elif name == "scale":
            t[0, 0], t[1, 1] = v[0], (v[1] if len(v) > 1 else v[0])
        elif name == "matrix":
            t[:2, :] = np.array(v).reshape(3, 2).T
        else:
            raise ValueError("unsupported SVG transform %s" % name)
        m = m @ t
    return m


def rasterize_polygons(polys, width, height, fill_rule="nonzero"):
    """Fills closed polylines (pixel coordinates, y down) sampled at pixel centres.

    A centre at exactly an edge's lower end counts like a half-open interval, so shared
    vertices are not counted twice."""
    mask = np.zeros((height, width), dtype=bool)
    if not polys:
        return mask
    p0 = np.concatenate(polys)
    p1 = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    x0, y0, x1, y1 = p0[:, 0], p0[:, 1], p1[:, 0], p1[:, 1]
    keep = y0 != y1
    x0, y0, x1, y1 = x0[keep], y0[keep], x1[keep], y1[keep]
    direction = np.where(y1 > y0, 1, -1)
    xc = np.arange(width) + 0.5
    for r in range(height):
        yc = r + 0.5
        hit = ((y0 <= yc) & (yc < y1)) | ((y1 <= yc) & (yc < y0))
        if not hit.any():
            continue
        xs = x0[hit] + (yc - y0[hit]) * (x1[hit] - x0[hit]) / (y1[hit] - y0[hit])
        left = xs[None, :] < xc[:, None]  # crossings left of each centre
        if fill_rule == "evenodd":
            mask[r] = (np.count_nonzero(left, axis=1) % 2) == 1
        else:
            mask[r] = (left.astype(np.int32) @ direction[hit]) != 0
    return mask


def _local(tag):
    return tag.rsplit("}", 1)[-1]


def rasterize_svg(svg_text, width, height):
    """Rasterises every <path> of an SVG onto a width x height pixel grid (its viewBox)."""
    root = ET.fromstring(svg_text)
    vb = [float(v) for v in NUMBER_RE.findall(root.get("viewBox", ""))]
    if len(vb) != 4:
        vb = [0.0, 0.0, float(width), float(height)]
    view = np.array([[width / vb[2], 0, -vb[0] * width / vb[2]],
                     [0, height / vb[3], -vb[1] * height / vb[3]], [0, 0, 1]])
    mask = np.zeros((height, width), dtype=bool)
    numbers = 0

    def walk(node, m, rule):
        nonlocal mask, numbers
        m = m @ _parse_transform(node.get("transform"))
        rule = node.get("fill-rule", rule)
        style = node.get("style", "")
        found = re.search(r"fill-rule\s*:\s*(\w+)", style)
        if found:
            rule = found.group(1)
        if _local(node.tag) == "path":
            d = node.get("d", "")
            numbers += len(NUMBER_RE.findall(d))
            polys = [(np.c_[p, np.ones(len(p))] @ m.T)[:, :2] for p in parse_svg_path(d)]
            mask |= rasterize_polygons(polys, width, height, rule)
        for child in node:
            walk(child, m, rule)

    walk(root, view, "nonzero")
    return mask, numbers


def run_potrace(mask, workdir, name):
    """Traces a foreground mask with potrace's defaults; returns (raster, numbers, svg path)."""
    h, w = mask.shape
    pbm = os.path.join(workdir, name + ".pbm")
    svg = os.path.join(workdir, name + ".potrace.svg")
    write_pbm(pbm, mask)
    subprocess.run(["potrace", "-b", "svg", "--flat", "-o", svg, pbm], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=60)
    with open(svg) as f:
        raster, numbers = rasterize_svg(f.read(), w, h)
    return raster, numbers, svg


# ----------------------------------------------------------------------------------------------
# Our side: CLI run, summary line, .scad parameters, OpenSCAD rendering

SUMMARY_RE = re.compile(r"IoU\s*[=:]?\s*(?P<iou>[0-9.]+)")
PRIMS_RE = re.compile(r"(?P<n>\d+)\s+primitives?")
EVALS_RE = re.compile(r"(?P<n>\d+)\s+evaluations?")
SECONDS_RE = re.compile(r"(?P<s>[0-9.]+)\s*s\b")
SCAD_ASSIGN_RE = re.compile(r"^\s*(\$?[A-Za-z_]\w*)\s*=\s*(.*?)\s*;", re.M)
SCAD_EXCLUDED = {"$fn", "$fa", "$fs", "segments", "pixel_size", "thickness"}
SCAD_PRIMITIVE_RE = re.compile(r"\b(square|circle|polygon)\s*\(")


def parse_summary(stderr):
    """Finds the CLI's final summary ('csgfit: IoU 0.98, 12 primitives, ..., 1.9 s') or a
    JSON stats line; returns a dict with the keys it found."""
    out = {}
    for line in stderr.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                obj = json.loads(line)
            except ValueError:
                continue
            stats = obj.get("stats", obj) if isinstance(obj, dict) else {}
            for key in ("iou", "primitives", "evaluations", "seconds"):
                if key in stats:
                    out[key] = stats[key]
    lines = [l for l in stderr.splitlines() if SUMMARY_RE.search(l) and PRIMS_RE.search(l)]
    if lines:
        line = lines[-1]
        out.setdefault("iou", float(SUMMARY_RE.search(line).group("iou")))
        out.setdefault("primitives", int(PRIMS_RE.search(line).group("n")))
        if EVALS_RE.search(line):
            out.setdefault("evaluations", int(EVALS_RE.search(line).group("n")))
        secs = SECONDS_RE.findall(line.split("evaluations")[-1])
        if secs:
            out.setdefault("seconds", float(secs[-1]))
    return out


def scad_numbers(text):
    """Counts the model's numbers: every `name = <number>;` assignment in the .scad (the named
    dimensions a user would edit) other than $fn/$fa/$fs, segments (the $fn Customizer
    variable), pixel_size and thickness. Vector literals (`p = [1, 2];`) count each number.
    Falls back to every numeric literal of the geometry when the file names no dimensions."""
    count = 0
    for name, value in SCAD_ASSIGN_RE.findall(text):
        if name in SCAD_EXCLUDED:
            continue
        if re.fullmatch(r"[\s\[\],+\-0-9.eE]*", value) and NUMBER_RE.search(value):
            count += len(NUMBER_RE.findall(value))
    if count == 0:
        body = re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)
        body = re.sub(r"\$f[nas]\s*=\s*[0-9.]+", "", body)
        count = len(NUMBER_RE.findall(body))
    return count


def cli_features(cli):
    """Which optional flags the CLI knows (it is built in parallel with this script)."""
    feats = {}
    try:
        proc = subprocess.run([cli, "image", "--help"], capture_output=True, text=True,
                              timeout=30)
        text = proc.stdout + proc.stderr
    except (OSError, subprocess.SubprocessError):
        text = ""
    for flag in ("--raster", "--json-stats", "--preview"):
        feats[flag] = re.search(re.escape(flag) + r"\b", text) is not None
    return feats


_scad_raster = None


def scad_raster_module():
    """scripts/scad_raster.py (written by another engineer): imported, never copied."""
    global _scad_raster
    if _scad_raster is None:
        if SCRIPT_DIR not in sys.path:
            sys.path.insert(0, SCRIPT_DIR)
        import scad_raster  # noqa: E402
        _scad_raster = scad_raster
    return _scad_raster


def render_scad(scad_path, width, height, pixel_size):
    """OpenSCAD's rendering of a 2D .scad on the input canvas, H x W bool, row 0 at top."""
    mod = scad_raster_module()
    for fname in ("rasterize_scad", "scad_to_mask", "render_scad", "rasterize", "raster_scad"):
        fn = getattr(mod, fname, None)
        if callable(fn):
            break
    else:
        raise RuntimeError("scripts/scad_raster.py exposes no known rasterise function")
    mask = fn(scad_path, width, height, pixel_size=pixel_size)
    if isinstance(mask, tuple):
        mask = mask[0]
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != (height, width):
        raise RuntimeError("OpenSCAD raster is %s, expected %s" % (mask.shape, (height, width)))
    return mask


def count_gt_primitives(path):
    with open(path) as f:
        tree = json.load(f)

    def walk(node):
        if isinstance(node, dict):
            return (1 if "type" in node else 0) + sum(walk(c) for c in node.get("children", []))
        if isinstance(node, list):
            return sum(walk(c) for c in node)
        return 0

    return walk(tree.get("tree", tree) if isinstance(tree, dict) else tree)


# ----------------------------------------------------------------------------------------------
# One bitmap


def bench_one(entry, args, feats, out_dir):
    name = entry["name"]
    row = {"name": name, "kind": entry["kind"], "width": entry["width"],
           "height": entry["height"], "status": "ok", "error": ""}
    errors = []
    grey = read_png_grey(os.path.join(args.bench_dir, entry["file"]))
    target = foreground_mask(grey, entry.get("foreground", "black"))
    h, w = target.shape
    masks = {"input": target}

    # Potrace baseline (independent of our CLI).
    try:
        pt_mask, pt_numbers, _ = run_potrace(target, out_dir, name)
        row["potrace_iou"] = iou(pt_mask, target)
        row["potrace_numbers"] = pt_numbers
        masks["potrace"] = pt_mask
    except Exception as exc:  # recorded, never fatal
        errors.append("potrace: %s" % exc)

    gt_file = entry.get("gt_file")
    if gt_file and os.path.exists(os.path.join(args.bench_dir, gt_file)):
        row["gt_primitives"] = count_gt_primitives(os.path.join(args.bench_dir, gt_file))

    if args.potrace_only:
        row["status"] = "potrace-only"
        row["error"] = "; ".join(errors)
        return row, masks

    scad = os.path.join(out_dir, name + ".scad")
    raster_png = os.path.join(out_dir, name + "_raster.png")
    for stale in (scad, raster_png):
        if os.path.exists(stale):
            os.remove(stale)
    cmd = [args.cli, "image", os.path.join(args.bench_dir, entry["file"]), "-o", scad,
           "--time", "%g" % args.time]
    if feats.get("--json-stats"):
        cmd.append("--json-stats")
    if feats.get("--raster"):
        cmd += ["--raster", raster_png]
    cmd += shlex.split(args.extra_args)
    row["command"] = " ".join(shlex.quote(c) for c in cmd)
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True,
                              timeout=args.time * 10 + 60)
        row["wall_s"] = time.monotonic() - t0
        row["exit_code"] = proc.returncode
        with open(os.path.join(out_dir, name + ".stderr.txt"), "w") as f:
            f.write(proc.stderr)
        if proc.returncode != 0:
            last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
            raise RuntimeError("csgfit exit %d: %s" % (proc.returncode, last[:200]))
        summary = parse_summary(proc.stderr)
        row["solver_iou"] = summary.get("iou", "")
        row["solver_primitives"] = summary.get("primitives", "")
        row["solver_evaluations"] = summary.get("evaluations", "")
        row["solver_seconds"] = summary.get("seconds", "")
        if not os.path.exists(scad):
            raise RuntimeError("csgfit exited 0 but wrote no .scad")
    except subprocess.TimeoutExpired:
        row["wall_s"] = time.monotonic() - t0
        row["status"] = "cli-timeout"
        row["error"] = "; ".join(errors + ["csgfit did not finish"])
        return row, masks
    except Exception as exc:
        row["status"] = "cli-fail"
        row["error"] = "; ".join(errors + [str(exc)])
        return row, masks

    with open(scad) as f:
        scad_text = f.read()
    row["our_numbers"] = scad_numbers(scad_text)
    if row["solver_primitives"] == "":
        row["solver_primitives"] = len(SCAD_PRIMITIVE_RE.findall(scad_text))
    if "gt_primitives" in row and row["solver_primitives"] != "":
        row["prim_gt_ratio"] = int(row["solver_primitives"]) / row["gt_primitives"]

    try:
        ours = render_scad(scad, w, h, args.pixel_size)
        row["scad_rendered"] = "yes"
        row["iou_openscad"] = iou(ours, target)
        masks["openscad"] = ours
    except Exception as exc:
        row["scad_rendered"] = "no"
        row["status"] = "openscad-fail"
        errors.append("OpenSCAD: %s" % str(exc).strip().splitlines()[-1][:200]
                      if str(exc).strip() else "OpenSCAD: failed")
    if "openscad" in masks and os.path.exists(raster_png):
        try:
            solver = foreground_mask(read_png_grey(raster_png))
            if solver.shape != target.shape:
                raise RuntimeError("solver raster is %s, input %s" % (solver.shape, target.shape))
            row["agreement_pct"] = 100.0 * np.count_nonzero(solver == masks["openscad"]) / solver.size
            row["solver_raster_iou"] = iou(solver, target)
        except Exception as exc:
            errors.append("solver raster: %s" % exc)
    row["error"] = "; ".join(errors)
    return row, masks


# ----------------------------------------------------------------------------------------------
# Pictures

def overlay(reference, model):
    """White background; black where both agree; red excess (model only); blue uncovered."""
    img = np.full(reference.shape + (3,), 255, dtype=np.uint8)
    img[reference & model] = (0, 0, 0)
    img[model & ~reference] = (220, 30, 30)
    img[reference & ~model] = (40, 90, 230)
    return img


def compose_picture(masks, path):
    ref = masks["input"]
    panels = [np.repeat(np.where(ref, 0, 255).astype(np.uint8)[..., None], 3, axis=2)]
    for key in ("openscad", "potrace"):
        if key in masks:
            panels.append(overlay(ref, masks[key]))
    h, w = ref.shape
    scale = max(1, 256 // max(h, w))
    gap = np.full((h * scale, 6, 3), 160, dtype=np.uint8)
    big = [np.kron(p, np.ones((scale, scale, 1), dtype=np.uint8)) for p in panels]
    parts = []
    for i, p in enumerate(big):
        if i:
            parts.append(gap)
        parts.append(p)
    write_png_rgb(path, np.concatenate(parts, axis=1))


def pick_pictures(entries, n):
    """Round-robin over categories: the first bitmap of each, then the second, ..."""
    by_kind = {}
    for e in entries:
        by_kind.setdefault(e["kind"], []).append(e["name"])
    order = [k for k in CATEGORY_LABELS if k in by_kind] + \
        [k for k in by_kind if k not in CATEGORY_LABELS]
    picked, depth = [], 0
    while len(picked) < n and any(len(by_kind[k]) > depth for k in order):
        for k in order:
            if len(picked) < n and len(by_kind[k]) > depth:
                picked.append(by_kind[k][depth])
        depth += 1
    return picked


# ----------------------------------------------------------------------------------------------
# Tables

CSV_FIELDS = ["name", "kind", "width", "height", "status", "wall_s", "exit_code", "solver_iou",
              "solver_primitives", "solver_evaluations", "solver_seconds", "scad_rendered",
              "iou_openscad", "agreement_pct", "solver_raster_iou", "our_numbers",
              "potrace_iou", "potrace_numbers", "gt_primitives", "prim_gt_ratio", "error",
              "command"]

TARGETS = {"mean_iou": 0.97, "median_iou": 0.98, "agreement_min": 99.5, "gt_ratio": 1.3,
           "median_wall": 2.5}


def _num(rows, key):
    out = []
    for r in rows:
        v = r.get(key, "")
        if v not in ("", None):
            try:
                out.append(float(v))
            except ValueError:
                pass
    return out


def _fmt(values, fn, digits, na="n/a"):
    return na if not values else ("%.*f" % (digits, fn(values)))


def _failed(r):
    return r.get("status") not in ("ok", "potrace-only")


def category_rows(rows):
    groups = {}
    for r in rows:
        groups.setdefault(r["kind"], []).append(r)
    order = [k for k in CATEGORY_LABELS if k in groups] + \
        [k for k in groups if k not in CATEGORY_LABELS]
    out = [(CATEGORY_LABELS.get(k, k), groups[k]) for k in order]
    gt = [r for r in rows if r.get("gt_primitives") not in ("", None)]
    if gt and len(gt) != len(rows):
        out.append(("with ground truth (parts + eye_in_diamond)", gt))
    out.append(("**all**", rows))
    return out


def markdown_table(rows):
    head = ("| category | n | mean IoU | median IoU | min IoU | mean prims | median wall s | "
            "OpenSCAD = solver raster, min % | potrace IoU | potrace numbers | our numbers | "
            "prims / ground truth | failed |")
    lines = [head, "|" + "|".join(["---"] + ["--:"] * 12) + "|"]
    for label, rs in category_rows(rows):
        ious = _num(rs, "iou_openscad")
        lines.append("| %s | " % label + " | ".join([
            "%d" % len(rs),
            _fmt(ious, statistics.mean, 4), _fmt(ious, statistics.median, 4),
            _fmt(ious, min, 4), _fmt(_num(rs, "solver_primitives"), statistics.mean, 1),
            _fmt(_num(rs, "wall_s"), statistics.median, 2),
            _fmt(_num(rs, "agreement_pct"), min, 2),
            _fmt(_num(rs, "potrace_iou"), statistics.mean, 4),
            _fmt(_num(rs, "potrace_numbers"), statistics.mean, 0),
            _fmt(_num(rs, "our_numbers"), statistics.mean, 0),
            _fmt(_num(rs, "prim_gt_ratio"), statistics.mean, 2, na="-"),
            "%d" % sum(_failed(r) for r in rs)]) + " |")
    return "\n".join(lines)


def acceptance(rows):
    """The project's targets (docs/BENCHMARKS.md) against this run: list of (text, ok)."""
    ious = _num(rows, "iou_openscad")
    agree = _num(rows, "agreement_pct")
    ratios = _num(rows, "prim_gt_ratio")
    walls = _num(rows, "wall_s")
    rendered = sum(r.get("scad_rendered") == "yes" for r in rows)
    checks = [
        ("every .scad renders in OpenSCAD: %d / %d" % (rendered, len(rows)),
         rendered == len(rows)),
        ("OpenSCAD rendering = solver raster on >= 99.5 %% of pixels: min %s %% (%d of %d "
         "bitmaps compared)" % (_fmt(agree, min, 2), len(agree), len(rows)),
         bool(agree) and len(agree) == len(rows)
         and min(agree) >= TARGETS["agreement_min"]),
        ("mean IoU >= 0.97: %s (%d of %d bitmaps rendered)"
         % (_fmt(ious, statistics.mean, 4), len(ious), len(rows)),
         len(ious) == len(rows) and statistics.mean(ious) >= TARGETS["mean_iou"]),
        ("median IoU >= 0.98: %s" % _fmt(ious, statistics.median, 4),
         len(ious) == len(rows) and statistics.median(ious) >= TARGETS["median_iou"]),
        ("primitives <= 1.3 x ground truth on average: %s" % _fmt(ratios, statistics.mean, 2),
         bool(ratios) and statistics.mean(ratios) <= TARGETS["gt_ratio"]),
        ("median wall time <= 2.5 s: %s" % _fmt(walls, statistics.median, 2),
         bool(walls) and statistics.median(walls) <= TARGETS["median_wall"]),
    ]
    if not ratios:
        checks[4] = ("primitives <= 1.3 x ground truth on average: n/a (no ground truth run)",
                     None)
    return checks


def potrace_table(rows):
    lines = ["| category | n | potrace IoU mean | median | min | potrace numbers mean |",
             "|---|--:|--:|--:|--:|--:|"]
    for label, rs in category_rows(rows):
        p = _num(rs, "potrace_iou")
        lines.append("| %s | %d | %s | %s | %s | %s |" % (
            label, len(rs), _fmt(p, statistics.mean, 4), _fmt(p, statistics.median, 4),
            _fmt(p, min, 4), _fmt(_num(rs, "potrace_numbers"), statistics.mean, 0)))
    return "\n".join(lines)


def git_commit():
    try:
        return subprocess.run(["git", "-C", REPO_DIR, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip() or "?"
    except (OSError, subprocess.SubprocessError):
        return "?"


def report(rows, args, feats, pictures):
    out = []
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    if args.potrace_only:
        out.append("Potrace baseline only (no csgfit run), %s, %d bitmaps.\n" % (when, len(rows)))
        out.append(potrace_table(rows))
        return "\n".join(out) + "\n"
    extra = (" " + args.extra_args) if args.extra_args else ""
    out.append("Measured %s, commit %s, `csgfit image --time %g%s`, %d bitmaps, --jobs %d, "
               "%d cores (%s).%s\n" % (
                   when, git_commit(), args.time, extra, len(rows), args.jobs,
                   os.cpu_count() or 0, platform.platform(terse=True),
                   "" if feats.get("--raster") else
                   " The CLI has no `--raster` yet: the agreement column is n/a."))
    out.append(markdown_table(rows))
    out.append("\nAcceptance targets:\n")
    for text, ok in acceptance(rows):
        mark = "n/a" if ok is None else ("PASS" if ok else "FAIL")
        out.append("- %s: %s" % (mark, text))
    failed = [r for r in rows if _failed(r)]
    if failed:
        out.append("\nFailures:\n")
        for r in failed:
            out.append("- `%s`: %s (%s)" % (r["name"], r["status"], r.get("error", "")))
    if pictures:
        out.append("\nInput | OpenSCAD rendering of our .scad | potrace, each overlaid on the "
                   "input (black: both, red: excess, blue: uncovered):\n")
        for name, rel in pictures:
            out.append("![%s](%s)" % (name, rel))
    return "\n".join(out) + "\n"


def write_doc(path, text):
    with open(path) as f:
        doc = f.read()
    begin, end = doc.find(DOC_BEGIN), doc.find(DOC_END)
    if begin < 0 or end < begin:
        raise SystemExit("%s has no %s ... %s section" % (path, DOC_BEGIN, DOC_END))
    doc = doc[:begin + len(DOC_BEGIN)] + "\n" + text + doc[end:]
    with open(path, "w") as f:
        f.write(doc)


# ----------------------------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", default=os.path.join(REPO_DIR, "build", "bin", "csgfit"))
    ap.add_argument("--bench-dir", default=DEFAULT_BENCH_DIR)
    ap.add_argument("--time", type=float, default=2.0, help="csgfit --time budget (s)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="bitmaps in parallel (default 1: the solver uses every core itself)")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="run only these bitmaps")
    ap.add_argument("--out", default=os.path.join(REPO_DIR, "bench-out", "2d"))
    ap.add_argument("--extra-args", default="", help="appended to every csgfit command")
    ap.add_argument("--pixel-size", type=float, default=1.0)
    ap.add_argument("--pictures", type=int, default=6,
                    help="side-by-side PNGs written to docs/img (one per category first)")
    ap.add_argument("--img-dir", default=os.path.join(REPO_DIR, "docs", "img"))
    ap.add_argument("--write-doc", nargs="?", const=os.path.join(REPO_DIR, "docs",
                                                                 "BENCHMARKS.md"),
                    metavar="MD", help="replace the bench2d section of docs/BENCHMARKS.md")
    ap.add_argument("--potrace-only", action="store_true",
                    help="only the potrace baseline (needs neither csgfit nor OpenSCAD)")
    args = ap.parse_args(argv)

    manifest = os.path.join(args.bench_dir, "manifest.json")
    if not os.path.exists(manifest):
        print("bench_2d: %s not found: skipped" % manifest)
        return 0
    with open(manifest) as f:
        entries = json.load(f)
    if isinstance(entries, dict):
        entries = entries.get("entries") or entries.get("bitmaps") or []
    if args.only:
        unknown = set(args.only) - {e["name"] for e in entries}
        if unknown:
            print("bench_2d: unknown bitmap(s): %s" % " ".join(sorted(unknown)), file=sys.stderr)
            return 2
        entries = [e for e in entries if e["name"] in set(args.only)]
    if shutil.which("potrace") is None:
        print("bench_2d: potrace not found (apt-get install potrace)", file=sys.stderr)
        return 2

    feats = {}
    if not args.potrace_only:
        if not (os.path.isfile(args.cli) and os.access(args.cli, os.X_OK)):
            print("bench_2d: CLI %s not found (build it, or pass --cli / --potrace-only)"
                  % args.cli, file=sys.stderr)
            return 2
        feats = cli_features(args.cli)
        try:
            scad_raster_module()
        except ImportError as exc:
            print("bench_2d: cannot import scripts/scad_raster.py: %s" % exc, file=sys.stderr)
            return 2
    os.makedirs(args.out, exist_ok=True)

    want_pics = set(pick_pictures(entries, args.pictures)) if not args.potrace_only else set()
    results = {}

    def task(entry):
        try:
            return bench_one(entry, args, feats, args.out)
        except Exception as exc:  # a bad bitmap must not abort the run
            return ({"name": entry["name"], "kind": entry["kind"], "width": entry["width"],
                     "height": entry["height"], "status": "error", "error": str(exc)}, {})

    t_start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = {pool.submit(task, e): e["name"] for e in entries}
        for fut in concurrent.futures.as_completed(futures):
            row, masks = fut.result()
            results[row["name"]] = (row, masks)
            print("%-26s %-13s IoU %-6s prims %-4s wall %-5s potrace %-6s %s" % (
                row["name"], row["status"],
                "%.4f" % row["iou_openscad"] if "iou_openscad" in row else "-",
                row.get("solver_primitives", "-"),
                "%.2f" % row["wall_s"] if "wall_s" in row else "-",
                "%.4f" % row["potrace_iou"] if "potrace_iou" in row else "-",
                row.get("error", "")), file=sys.stderr, flush=True)
    rows = [results[e["name"]][0] for e in entries]

    pictures = []
    if want_pics:
        os.makedirs(args.img_dir, exist_ok=True)
        for name in pick_pictures(entries, args.pictures):
            masks = results[name][1]
            if "openscad" not in masks:
                continue
            path = os.path.join(args.img_dir, "bench2d_%s.png" % name)
            compose_picture(masks, path)
            pictures.append((name, os.path.relpath(path, os.path.join(REPO_DIR, "docs"))))

    csv_path = os.path.join(args.out, "results.csv")
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow({k: ("%.6g" % v if isinstance(v, float) else v)
                             for k, v in r.items()})

    text = report(rows, args, feats, pictures)
    print(text)
    print("bench_2d: %d bitmaps in %.0f s; results in %s" % (
        len(rows), time.monotonic() - t_start, csv_path), file=sys.stderr)
    if args.write_doc:
        write_doc(args.write_doc, text)
        print("bench_2d: updated %s" % args.write_doc, file=sys.stderr)
    return 1 if any(_failed(r) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
