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
import json
import os
import re
import statistics
import struct
import subprocess
import sys
import time
import zlib

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import benchlib  # noqa: E402  (what bench_3d.py does the same way)
import potrace_baseline  # noqa: E402
import scad_raster  # noqa: E402  (OpenSCAD's rendering, and the PNG decoding it has)
from benchlib import REPO_DIR, fmt, iou, numeric  # noqa: E402
from potrace_baseline import NUMBER_RE  # noqa: E402

PROG = "bench_2d"

# Display order and labels of the manifest's `kind` values.
CATEGORY_LABELS = {
    "glyph": "glyph (DejaVu letters)",
    "icon": "icon (Adwaita symbolic)",
    "synthetic": "part (random CSG, ground truth)",
    "topopt": "topopt (SIMP results)",
    "csgnet_cad": "csgnet_cad (CSGNet 2D CAD)",
}

# ----------------------------------------------------------------------------------------------
# PNG input and output (numpy + zlib, so the script needs no imaging library)


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
    for kind, body in scad_raster.png_chunks(data):
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
    if depth != 8 or interlace or channels is None:
        raise ValueError("%s: only 8-bit non-interlaced grey/RGB(A) PNGs without PIL" % path)
    px = scad_raster.png_unfilter(zlib.decompress(idat), h, w * channels, channels)
    px = px.reshape(h, w, channels)
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


def foreground_mask(grey, foreground="black"):
    """The bitmaps are clean black/white; the shape is the `foreground` colour."""
    return grey < 128 if foreground != "white" else grey >= 128


# ----------------------------------------------------------------------------------------------
# Our side: CLI run, .scad parameters, OpenSCAD rendering

SCAD_ASSIGN_RE = re.compile(r"^\s*(\$?[A-Za-z_]\w*)\s*=\s*(.*?)\s*;", re.M)
SCAD_EXCLUDED = {"$fn", "$fa", "$fs", "segments", "pixel_size", "thickness"}
SCAD_PRIMITIVE_RE = re.compile(r"\b(square|circle|polygon)\s*\(")


def summary_cells(stderr):
    """The solver columns from the CLI's stderr, a JSON stats line first (--json-stats)."""
    return benchlib.solver_cells(benchlib.parse_summary(stderr, json_stats=True))


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


def render_scad(scad_path, width, height, pixel_size):
    """OpenSCAD's rendering of a 2D .scad on the input canvas, H x W bool, row 0 at top."""
    mask = np.asarray(scad_raster.rasterize_scad(scad_path, width, height,
                                                 pixel_size=pixel_size), dtype=bool)
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
    """Potrace, csgfit and OpenSCAD on one bitmap: its CSV row and the masks to picture."""
    name = entry["name"]
    row = {"name": name, "kind": entry["kind"], "width": entry["width"],
           "height": entry["height"], "status": "ok", "error": ""}
    errors = []
    grey = read_png_grey(os.path.join(args.bench_dir, entry["file"]))
    target = foreground_mask(grey, entry.get("foreground", "black"))
    masks = {"input": target}
    score_potrace(row, masks, out_dir, errors)

    gt_file = entry.get("gt_file")
    if gt_file and os.path.exists(os.path.join(args.bench_dir, gt_file)):
        row["gt_primitives"] = count_gt_primitives(os.path.join(args.bench_dir, gt_file))

    if args.potrace_only:
        row["status"] = "potrace-only"
        row["error"] = "; ".join(errors)
        return row, masks

    scad = os.path.join(out_dir, name + ".scad")
    raster_png = os.path.join(out_dir, name + "_raster.png")
    failure = fit_one(entry, row, args, feats, scad, raster_png)
    if failure:
        row["error"] = "; ".join(errors + [failure])
        return row, masks
    count_scad(row, scad)
    score_one(row, masks, scad, raster_png, args.pixel_size, errors)
    row["error"] = "; ".join(errors)
    return row, masks


def score_potrace(row, masks, out_dir, errors):
    """Potrace's trace of the input (independent of our CLI), scored like ours."""
    target = masks["input"]
    try:
        pt_mask, pt_numbers, _ = potrace_baseline.run_potrace(target, out_dir, row["name"])
        row["potrace_iou"] = iou(pt_mask, target)
        row["potrace_numbers"] = pt_numbers
        masks["potrace"] = pt_mask
    except Exception as exc:  # recorded, never fatal
        errors.append("potrace: %s" % exc)


def fit_one(entry, row, args, feats, scad, raster_png):
    """csgfit image on the bitmap; None, or the error text when it wrote no .scad."""
    benchlib.remove_files(scad, raster_png)
    options = []
    if feats.get("--json-stats"):
        options.append("--json-stats")
    if feats.get("--raster"):
        options += ["--raster", raster_png]
    cmd = benchlib.csgfit_command(args, "image", os.path.join(args.bench_dir, entry["file"]),
                                  scad, options)
    log = os.path.join(os.path.dirname(scad), entry["name"] + ".stderr.txt")
    return benchlib.run_cli(cmd, row, scad, log, args.time * 10 + 60, summary_cells)


def count_scad(row, scad):
    """Our numbers and primitives, read from the .scad where the summary has no count."""
    with open(scad) as f:
        scad_text = f.read()
    row["our_numbers"] = scad_numbers(scad_text)
    if row["solver_primitives"] == "":
        row["solver_primitives"] = len(SCAD_PRIMITIVE_RE.findall(scad_text))
    if "gt_primitives" in row and row["solver_primitives"] != "":
        row["prim_gt_ratio"] = int(row["solver_primitives"]) / row["gt_primitives"]


def score_one(row, masks, scad, raster_png, pixel_size, errors):
    """OpenSCAD's rendering of our .scad against the input, and against the solver's raster."""
    target = masks["input"]
    h, w = target.shape
    try:
        ours = render_scad(scad, w, h, pixel_size)
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
    order = benchlib.kind_order(by_kind, CATEGORY_LABELS)
    picked, depth = [], 0
    while len(picked) < n and any(len(by_kind[k]) > depth for k in order):
        for k in order:
            if len(picked) < n and len(by_kind[k]) > depth:
                picked.append(by_kind[k][depth])
        depth += 1
    return picked


def write_pictures(entries, results, args):
    """The side-by-side PNGs of the picked bitmaps: [(name, path relative to docs/)]."""
    picked = pick_pictures(entries, args.pictures)
    if picked:
        os.makedirs(args.img_dir, exist_ok=True)
    masks_of = {e["name"]: masks for e, (_, masks) in zip(entries, results)}
    pictures = []
    for name in picked:
        masks = masks_of[name]
        if "openscad" not in masks:
            continue
        path = os.path.join(args.img_dir, "bench2d_%s.png" % name)
        compose_picture(masks, path)
        pictures.append((name, os.path.relpath(path, os.path.join(REPO_DIR, "docs"))))
    return pictures


# ----------------------------------------------------------------------------------------------
# Tables

CSV_FIELDS = ["name", "kind", "width", "height", "status", "wall_s", "exit_code", "solver_iou",
              "solver_primitives", "solver_evaluations", "solver_seconds", "scad_rendered",
              "iou_openscad", "agreement_pct", "solver_raster_iou", "our_numbers",
              "potrace_iou", "potrace_numbers", "gt_primitives", "prim_gt_ratio", "error",
              "command"]

TARGETS = {"mean_iou": 0.97, "median_iou": 0.98, "agreement_min": 99.5, "gt_ratio": 1.3,
           "median_wall": 2.5}


def _failed(r):
    return r.get("status") not in ("ok", "potrace-only")


def category_rows(rows):
    out = benchlib.kind_groups(rows, CATEGORY_LABELS)
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
        ious = numeric(rs, "iou_openscad")
        lines.append("| %s | " % label + " | ".join([
            "%d" % len(rs),
            fmt(ious, statistics.mean, 4), fmt(ious, statistics.median, 4),
            fmt(ious, min, 4), fmt(numeric(rs, "solver_primitives"), statistics.mean, 1),
            fmt(numeric(rs, "wall_s"), statistics.median, 2),
            fmt(numeric(rs, "agreement_pct"), min, 2),
            fmt(numeric(rs, "potrace_iou"), statistics.mean, 4),
            fmt(numeric(rs, "potrace_numbers"), statistics.mean, 0),
            fmt(numeric(rs, "our_numbers"), statistics.mean, 0),
            fmt(numeric(rs, "prim_gt_ratio"), statistics.mean, 2, na="-"),
            "%d" % sum(_failed(r) for r in rs)]) + " |")
    return "\n".join(lines)


def acceptance(rows):
    """The project's targets (docs/BENCHMARKS.md) against this run: list of (text, ok)."""
    ious = numeric(rows, "iou_openscad")
    agree = numeric(rows, "agreement_pct")
    ratios = numeric(rows, "prim_gt_ratio")
    walls = numeric(rows, "wall_s")
    rendered = sum(r.get("scad_rendered") == "yes" for r in rows)
    checks = [
        ("every .scad renders in OpenSCAD: %d / %d" % (rendered, len(rows)),
         rendered == len(rows)),
        ("OpenSCAD rendering = solver raster on >= 99.5 %% of pixels: min %s %% (%d of %d "
         "bitmaps compared)" % (fmt(agree, min, 2), len(agree), len(rows)),
         bool(agree) and len(agree) == len(rows)
         and min(agree) >= TARGETS["agreement_min"]),
        ("mean IoU >= 0.97: %s (%d of %d bitmaps rendered)"
         % (fmt(ious, statistics.mean, 4), len(ious), len(rows)),
         len(ious) == len(rows) and statistics.mean(ious) >= TARGETS["mean_iou"]),
        ("median IoU >= 0.98: %s" % fmt(ious, statistics.median, 4),
         len(ious) == len(rows) and statistics.median(ious) >= TARGETS["median_iou"]),
        ("primitives <= 1.3 x ground truth on average: %s" % fmt(ratios, statistics.mean, 2),
         bool(ratios) and statistics.mean(ratios) <= TARGETS["gt_ratio"]),
        ("median wall time <= 2.5 s: %s" % fmt(walls, statistics.median, 2),
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
        p = numeric(rs, "potrace_iou")
        lines.append("| %s | %d | %s | %s | %s | %s |" % (
            label, len(rs), fmt(p, statistics.mean, 4), fmt(p, statistics.median, 4),
            fmt(p, min, 4), fmt(numeric(rs, "potrace_numbers"), statistics.mean, 0)))
    return "\n".join(lines)


def report(rows, args, feats, pictures):
    if args.potrace_only:
        return "\n".join([
            "Potrace baseline only (no csgfit run), %s, %d bitmaps.\n" % (benchlib.now(),
                                                                         len(rows)),
            potrace_table(rows)]) + "\n"
    out = [benchlib.measured_line(
        args, "image", "%d bitmaps" % len(rows),
        note="" if feats.get("--raster") else
        " The CLI has no `--raster` yet: the agreement column is n/a.")]
    out.append(markdown_table(rows))
    out.append("\nAcceptance targets:\n")
    out += benchlib.outcome_lines(acceptance(rows), [r for r in rows if _failed(r)])
    if pictures:
        out.append("\nInput | OpenSCAD rendering of our .scad | potrace, each overlaid on the "
                   "input (black: both, red: excess, blue: uncovered):\n")
        for name, rel in pictures:
            out.append("![%s](%s)" % (name, rel))
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------------


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    benchlib.add_run_args(ap, "2d", "bitmaps", 2.0)
    benchlib.add_output_args(ap, "2d")
    ap.add_argument("--pixel-size", type=float, default=1.0)
    ap.add_argument("--pictures", type=int, default=6,
                    help="side-by-side PNGs written to docs/img (one per category first)")
    ap.add_argument("--img-dir", default=os.path.join(REPO_DIR, "docs", "img"))
    benchlib.add_doc_arg(ap, "2d")
    ap.add_argument("--potrace-only", action="store_true",
                    help="only the potrace baseline (needs neither csgfit nor OpenSCAD)")
    return ap.parse_args(argv)


def check_tools(args):
    """The CLI's optional flags, or an exit status when a tool the run needs is missing."""
    if benchlib.missing_tool(PROG, "potrace"):
        return None, 2
    if args.potrace_only:
        return {}, None
    if benchlib.missing_cli(PROG, args.cli, "--cli / --potrace-only"):
        return None, 2
    return cli_features(args.cli), None


# The stderr line per bitmap: (label, key, format, width) after its name and status.
PROGRESS = [("IoU", "iou_openscad", "%.4f", 6), ("prims", "solver_primitives", None, 4),
            ("wall", "wall_s", "%.2f", 5), ("potrace", "potrace_iou", "%.4f", 6)]


def main(argv=None):
    args = parse_args(argv)
    entries, status = benchlib.load_entries(args, PROG, ("entries", "bitmaps"), "bitmap")
    if entries is None:
        return status
    feats, status = check_tools(args)
    if feats is None:
        return status
    os.makedirs(args.out, exist_ok=True)

    def task(entry):
        try:
            return bench_one(entry, args, feats, args.out)
        except Exception as exc:  # a bad bitmap must not abort the run
            return ({"name": entry["name"], "kind": entry["kind"], "width": entry["width"],
                     "height": entry["height"], "status": "error", "error": str(exc)}, {})

    t_start = time.monotonic()
    results = benchlib.run_all(task, entries, args.jobs,
                               lambda result: benchlib.print_progress(result[0], 26, PROGRESS))
    rows = [row for row, _ in results]
    pictures = [] if args.potrace_only else write_pictures(entries, results, args)
    text = report(rows, args, feats, pictures)
    benchlib.finish(PROG, "2d", "bitmaps", rows, CSV_FIELDS, text, args, t_start)
    return 1 if any(_failed(r) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
