#!/usr/bin/python3
"""Morph benchmark (issue 13): csgfit morph -> animated .scad -> OpenSCAD at morph = 0 .. 1.

For every pair of PAIRS_2D (bitmaps of ../shared/benchmarks/2d) this runs
`csgfit morph A B -o OUT.scad --time T --seed S`, and `csgfit image` on A and on B alone (the
"own fit" each end is compared with). The judge is OpenSCAD, never the solver: the .scad is
rendered with -D morph=0, 0.25, 0.5, 0.75, 1 (scripts/scad_raster.py) and the ends are scored
by IoU against A's and B's bitmaps; the middle frames must not be empty; OpenSCAD's flattened
tree (-o x.csg) must have the same operators and primitives in the same order at 0 and 1.
For every pair of PAIRS_3D (synthetic models of ../shared/benchmarks/3d/inversecsg, whose
ground-truth csg.scad OpenSCAD renders to the input STL) the morph's .scad is rendered to STL at
morph = 0 and 1 and voxelised by scripts/stl_voxelize.py against the ground truth on one grid.

Writes --out/results.csv, a Markdown report (and with --write-doc the section between
<!-- benchmorph:begin/end --> of docs/BENCHMARKS.md) and one frame strip per 2D pair,
docs/img/morph_<a>_<b>.png. Runs on Debian's /usr/bin/python3 with numpy only. A failure on one
pair is recorded, never aborts the run; the exit status is 1 if any acceptance line fails.
"""

import argparse
import os
import re
import statistics
import sys
import time

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import bench_2d  # noqa: E402  (write_png_rgb: PNG output without an imaging library)
import bench_3d  # noqa: E402  (OFF/STL reading, OpenSCAD to STL, the voxel IoU)
import benchlib  # noqa: E402
import scad_raster  # noqa: E402  (OpenSCAD's 2D rendering and the bitmap reader)
from benchlib import REPO_DIR, SHARED_BENCH_DIR, fmt, iou, numeric  # noqa: E402

PROG = "bench_morph"

# The seed's two pairs (Figs. 13-14) first, then pairs chosen before any run, each of two
# bitmaps of the same canvas and a similar ink area: easy ones (shapes that share most of their
# parts) and hard ones (different topology: holes appear or vanish, parts split).
PAIRS_2D = [
    ("glyph_b_lower", "glyph_i_lower", "seed, Fig. 13: hole and dot"),
    ("glyph_P", "glyph_E", "seed, Fig. 14: hole to arms"),
    ("glyph_R", "glyph_P", "easy: R less its leg"),
    ("glyph_A", "glyph_8", "hard: one hole to two"),
    ("glyph_g_lower", "glyph_b_lower", "hard: descender to ascender"),
    ("icon_drive_harddisk", "icon_battery", "easy: box to box"),
    ("icon_media_playback_start", "icon_go_home", "easy: triangle to house"),
    ("icon_zoom_in", "icon_printer", "hard: disc and handle to boxes"),
    ("icon_edit_cut", "icon_document_save", "hard: scissors to floppy"),
]

# Synthetic InverseCSG models that share most of their primitives.
PAIRS_3D = [
    ("two_cuboids", "three_cuboids"),
    ("one_sphere_two_cuboids", "two_spheres_one_cuboid"),
]

FRAMES = (0.0, 0.25, 0.5, 0.75, 1.0)
TARGETS = {"iou_2d": 0.95, "own_fit_gap": 0.02, "iou_3d": 0.90}

# Seed 000 gives one count of trees evaluated for a bitmap of its morphing tests: 2,824 for
# 'P' fitted alone (Fig. 9). It gives none for the morph runs themselves (Figs. 13-14).
PAPER_TREES = {"glyph_P": 2824}

# "csgfit: morph IoU 0.9737 (A) and 1.0000 (B), 5 primitives (3 seen in one shape only),
#  15316 trees, 7036385 evaluations, 6.82 s (converged)"
MORPH_RE = re.compile(
    r"morph IoU (?P<iou_a>[0-9.]+) \(A\) and (?P<iou_b>[0-9.]+) \(B\), (?P<prims>\d+) "
    r"primitives? \((?P<single>\d+) seen in one shape only\), (?P<trees>\d+) trees?, "
    r"(?P<evals>\d+) evaluations?, (?P<secs>[0-9.]+) s \((?P<stop>[^()]*)\)")
TREES_RE = re.compile(r"(\d+)\s+trees?\b")

# ----------------------------------------------------------------------------------------------
# The CLI runs


def threads(args):
    """Threads per run: the cores shared by the --jobs runs (a run with more would only slow
    its neighbour, and --seed is reproducible for a given thread count)."""
    return max(1, (os.cpu_count() or 1) // max(1, args.jobs))


def run(args, row, words, out, budget, log):
    """One csgfit command (its words after the CLI) with --time, --seed and --threads."""
    cmd = [args.cli] + words + ["-o", out, "--time", "%g" % budget, "--seed", str(args.seed),
                                "--threads", str(threads(args))]
    benchlib.remove_files(out)
    return benchlib.run_cli(cmd, row, out, log, budget * 3 + 120, lambda err: {})


def morph_summary(row, log):
    """The solver's numbers from the morph's summary line into `row`."""
    with open(log) as f:
        m = MORPH_RE.search(f.read())
    if m:
        row.update({"solver_iou_a": float(m["iou_a"]), "solver_iou_b": float(m["iou_b"]),
                    "primitives": int(m["prims"]), "single": int(m["single"]),
                    "trees": int(m["trees"]), "evaluations": int(m["evals"]),
                    "solver_s": float(m["secs"]), "stop": m["stop"]})


# ----------------------------------------------------------------------------------------------
# OpenSCAD's flattened tree

CSG_TOKEN_RE = re.compile(r"[A-Za-z_]\w*(?=\s*\()|[{}]")
CSG_PRIMITIVES = {"square", "circle", "polygon", "cube", "sphere", "cylinder", "polyhedron"}


def csg_signature(scad, t, work, timeout):
    """The node names and braces of OpenSCAD's flattened tree at morph = t, numbers ignored."""
    csg = os.path.join(work, "%s.%g.csg" % (os.path.basename(scad), t))
    benchlib.remove_files(csg)
    scad_raster._run_openscad(scad_raster.define_args({"morph": t}) + ["-o", csg, scad],
                              timeout)
    with open(csg) as f:
        return CSG_TOKEN_RE.findall(f.read())


def same_tree(row, scad, work, timeout):
    """row["same_tree"]: yes when the flattened trees at 0 and 1 agree node for node."""
    sig0, sig1 = (csg_signature(scad, t, work, timeout) for t in (0, 1))
    row["same_tree"] = "yes" if sig0 == sig1 else "no"
    row["csg_primitives"] = sum(tok in CSG_PRIMITIVES for tok in sig0)


# ----------------------------------------------------------------------------------------------
# 2D


def bitmap(args, name):
    return os.path.join(args.bench_dir, name + ".png")


def own_fit(args, name):
    """`csgfit image` on one bitmap, judged by OpenSCAD: its row."""
    row = {"name": name, "kind": "image", "status": "ok"}
    scad = os.path.join(args.out, "own_%s.scad" % name)
    log = os.path.join(args.out, "own_%s.stderr.txt" % name)
    err = run(args, row, ["image", bitmap(args, name)], scad, args.time, log)
    if err:
        row["error"] = err
        return row
    with open(log) as f:
        trees = TREES_RE.findall(f.read())
    row["trees"] = int(trees[-1]) if trees else ""
    target = scad_raster.read_mask(bitmap(args, name))
    h, w = target.shape
    row["iou"] = iou(scad_raster.rasterize_scad(scad, w, h, 1.0), target)
    return row


def morph_2d(args, pair):
    """`csgfit morph A B` on two bitmaps, judged by OpenSCAD: its row and its frames."""
    a, b, note = pair
    row = {"name": "%s -> %s" % (a, b), "kind": "morph2d", "a": a, "b": b, "note": note,
           "status": "ok"}
    stem = os.path.join(args.out, "morph_%s_%s" % (a, b))
    err = run(args, row, ["morph", bitmap(args, a), bitmap(args, b)], stem + ".scad",
              args.time, stem + ".stderr.txt")
    if err:
        row["error"] = err
        return row, {}
    morph_summary(row, stem + ".stderr.txt")
    frames = render_frames(stem + ".scad", scad_raster.read_mask(bitmap(args, a)).shape)
    score_frames(row, frames, args)
    same_tree(row, stem + ".scad", args.out, args.openscad_timeout)
    return row, frames


def render_frames(scad, shape):
    """OpenSCAD's rendering at each of FRAMES on the bitmaps' canvas: {t: mask}."""
    h, w = shape
    return {t: np.asarray(scad_raster.rasterize_scad(scad, w, h, 1.0, defines={"morph": t}),
                          dtype=bool) for t in FRAMES}


def score_frames(row, frames, args):
    """IoU of the ends against A and B; the middle frames' ink (0 = an empty frame)."""
    row["iou_a"] = iou(frames[0.0], scad_raster.read_mask(bitmap(args, row["a"])))
    row["iou_b"] = iou(frames[1.0], scad_raster.read_mask(bitmap(args, row["b"])))
    middle = [int(frames[t].sum()) for t in FRAMES[1:-1]]
    row["middle_pixels"] = "/".join(map(str, middle))
    row["frames_ok"] = "yes" if min(middle) > 0 else "no"


# ----------------------------------------------------------------------------------------------
# 3D


def model_stl(args, name):
    """The synthetic model's ground truth rendered by OpenSCAD (cached in --out)."""
    return bench_3d.cached_stl(os.path.join(args.bench_dir_3d, name, "csg.scad"),
                               os.path.join(args.out, "gt_%s.stl" % name),
                               args.openscad_timeout)


def morph_3d(args, pair):
    """`csgfit morph A.stl B.stl`, both ends rendered by OpenSCAD and voxelised: its row."""
    a, b = pair
    row = {"name": "%s -> %s" % (a, b), "kind": "morph3d", "a": a, "b": b, "status": "ok"}
    stem = os.path.join(args.out, "morph3d_%s_%s" % (a, b))
    meshes = [model_stl(args, a), model_stl(args, b)]
    err = run(args, row, ["morph"] + meshes, stem + ".scad", args.time_3d,
              stem + ".stderr.txt")
    if err:
        row["error"] = err
        return row
    morph_summary(row, stem + ".stderr.txt")
    for key, t, mesh in (("iou_a", 0, meshes[0]), ("iou_b", 1, meshes[1])):
        stl = "%s.%d.stl" % (stem, t)
        bench_3d.openscad_stl(stem + ".scad", stl, args.openscad_timeout, {"morph": t})
        row[key], n = bench_3d.volume_iou(bench_3d.read_mesh(mesh), bench_3d.read_mesh(stl),
                                          args.grid)
        row["grid_" + key[-1]] = "x".join(map(str, n))
    same_tree(row, stem + ".scad", args.out, args.openscad_timeout)
    return row


# ----------------------------------------------------------------------------------------------
# Pictures


def frame_strip(frames, path):
    """The frames side by side, 128 px high: black shape on white, grey gaps."""
    panels = []
    for t in FRAMES:
        mask = frames[t]
        step = max(1, int(np.ceil(mask.shape[0] / 128.0)))
        mask = mask[::step, ::step]  # never above 128 px (the bitmaps are 128 already)
        if panels:
            panels.append(np.full((mask.shape[0], 4), 160, dtype=np.uint8))
        panels.append(np.where(mask, 0, 255).astype(np.uint8))
    grey = np.concatenate(panels, axis=1)
    bench_2d.write_png_rgb(path, np.repeat(grey[..., None], 3, axis=2))


def write_strips(results, args):
    """One strip per 2D pair with frames: [(row, path relative to the doc)]. They go to
    --img-dir with --write-doc, else to --out (a trial run leaves docs/ alone)."""
    img_dir = args.img_dir if args.write_doc else args.out
    doc_dir = os.path.dirname(os.path.abspath(args.write_doc or os.path.join(REPO_DIR, "docs",
                                                                             "x.md")))
    os.makedirs(img_dir, exist_ok=True)
    out = []
    for row, frames in results:
        if len(frames) == len(FRAMES):
            path = os.path.join(img_dir, "morph_%s_%s.png" % (row["a"], row["b"]))
            frame_strip(frames, path)
            out.append((row, os.path.relpath(path, doc_dir)))
    return out


# ----------------------------------------------------------------------------------------------
# The report


def attach_own_fits(rows2d, own):
    """Each pair's own-fit IoUs and the gap (morph end minus own fit, negative = worse)."""
    for r in rows2d:
        for end in ("a", "b"):
            fit = own.get(r[end], {})
            if "iou" in fit:
                r["own_" + end] = fit["iou"]
                if "iou_" + end in r:
                    r["gap_" + end] = r["iou_" + end] - fit["iou"]


def c(row, key, digits=4):
    return benchlib.cell(row, key, digits)


def table_2d(rows):
    lines = ["| pair | IoU A at 0 | own fit A | gap | IoU B at 1 | own fit B | gap | solver A / B "
             "| primitives (one shape only) | frames 0.25/0.5/0.75 px | same tree "
             "| wall s (stop) |",
             "|---|" + "--:|" * 11]
    for r in rows:
        lines.append(("| %s | %s | %s | %s | %s | %s | %s | %s / %s | %s (%s) | %s | %s "
                      "| %s (%s) |") % (
            r["name"], c(r, "iou_a"), c(r, "own_a"), c(r, "gap_a", 3), c(r, "iou_b"),
            c(r, "own_b"), c(r, "gap_b", 3), c(r, "solver_iou_a"), c(r, "solver_iou_b"),
            c(r, "primitives", None), c(r, "single", None), c(r, "middle_pixels", None),
            c(r, "same_tree", None), c(r, "wall_s", 1), c(r, "stop", None)))
    return "\n".join(lines)


def table_3d(rows):
    lines = ["| pair | IoU A at 0 | IoU B at 1 | solver A / B | primitives (one shape only) | "
             "same tree | grid | stop | wall s |", "|---|" + "--:|" * 8]
    for r in rows:
        lines.append("| %s | %s | %s | %s / %s | %s (%s) | %s | %s | %s | %s |" % (
            r["name"], c(r, "iou_a"), c(r, "iou_b"), c(r, "solver_iou_a"),
            c(r, "solver_iou_b"), c(r, "primitives", None), c(r, "single", None),
            c(r, "same_tree", None), c(r, "grid_a", None), c(r, "stop", None),
            c(r, "wall_s", 1)))
    return "\n".join(lines)


def seed_pairs(rows2d):
    """The rows of the seed's own pairs (the first two of PAIRS_2D)."""
    seed = {p[:2] for p in PAIRS_2D[:2]}
    return [r for r in rows2d if (r["a"], r["b"]) in seed]


def trees_table(rows2d, own):
    """Trees evaluated: the morph's and each shape's own fit, beside seed 000's counts."""
    lines = ["| pair | morph: trees | evaluations | own fit A / B: trees | seed 000 |",
             "|---|--:|--:|--:|---|"]
    for r in seed_pairs(rows2d):
        paper = ["'%s' alone: %s" % (n.split("_")[1], format(PAPER_TREES[n], ","))
                 for n in (r["a"], r["b"]) if n in PAPER_TREES]
        lines.append("| %s | %s | %s | %s / %s | morph: not reported%s |" % (
            r["name"], c(r, "trees", None), c(r, "evaluations", None),
            c(own.get(r["a"], {}), "trees", None), c(own.get(r["b"], {}), "trees", None),
            "".join("; " + p for p in paper)))
    return "\n".join(lines)


def count_line(text, rows, pred):
    """An acceptance line on every row: (text with n / N, all rows pass)."""
    if not rows:
        return "%s: not run" % text, None
    n = sum(1 for r in rows if pred(r))
    return "%s: %d / %d" % (text, n, len(rows)), n == len(rows)


def acceptance(rows2d, rows3d):
    t = TARGETS
    ends = numeric(rows2d, "iou_a") + numeric(rows2d, "iou_b")
    gaps = numeric(rows2d, "gap_a") + numeric(rows2d, "gap_b")
    ends3 = numeric(rows3d, "iou_a") + numeric(rows3d, "iou_b")
    return [
        count_line("2D: OpenSCAD's rendering matches A at morph = 0 and B at 1 with IoU >= %.2f "
                   "(min %s)" % (t["iou_2d"], fmt(ends, min, 4)), rows2d,
                   lambda r: min(r.get("iou_a", 0), r.get("iou_b", 0)) >= t["iou_2d"]),
        count_line("2D: both ends within %.2f of the shape's own fit (`csgfit image`, same "
                   "budget; worst gap %s)" % (t["own_fit_gap"], fmt(gaps, min, 4)), rows2d,
                   lambda r: "gap_a" in r and "gap_b" in r
                   and min(r["gap_a"], r["gap_b"]) >= -t["own_fit_gap"]),
        count_line("2D: the frames at 0.25, 0.5, 0.75 render and are not empty", rows2d,
                   lambda r: r.get("frames_ok") == "yes"),
        count_line("OpenSCAD's flattened tree (.csg) has the same operators and primitives in "
                   "the same order at 0 and 1 (2D and 3D)", rows2d + rows3d,
                   lambda r: r.get("same_tree") == "yes"),
        count_line("trees evaluated reported beside the paper's counts for its pairs",
                   seed_pairs(rows2d), lambda r: "trees" in r),
        count_line("3D: IoU >= %.2f at both ends (min %s)" % (t["iou_3d"], fmt(ends3, min, 4)),
                   rows3d, lambda r: min(r.get("iou_a", 0), r.get("iou_b", 0)) >= t["iou_3d"]),
    ]


def medians_line(rows2d, own, rows3d):
    med = lambda rs, k: fmt(numeric(rs, k), statistics.median, 1)  # noqa: E731
    own_rows = list(own.values())
    return ("Median wall time: 2D morph %s s (solver %s s), own fits %s s, 3D morph %s s."
            % (med(rows2d, "wall_s"), med(rows2d, "solver_s"), med(own_rows, "wall_s"),
               med(rows3d, "wall_s")))


def report(rows2d, own, rows3d, strips, args):
    out = [("Measured %s, commit %s (the CLI %s), `csgfit morph --time %g --seed %d --threads %d`"
            " (3D: --time %g), own fits `csgfit image --time %g`, %d 2D and %d 3D pairs, "
            "--jobs %d, %d cores.\n") % (
        benchlib.now(), benchlib.git_commit(), args.cli, args.time, args.seed, threads(args),
        args.time_3d, args.time, len(rows2d), len(rows3d), args.jobs, os.cpu_count() or 0)]
    out += [table_2d(rows2d), ""] + ([table_3d(rows3d), ""] if rows3d else [])
    out += [medians_line(rows2d, own, rows3d), "",
            "Trees evaluated:\n", trees_table(rows2d, own), "\nAcceptance:\n"]
    out += benchlib.outcome_lines(acceptance(rows2d, rows3d),
                                  [r for r in rows2d + rows3d + list(own.values())
                                   if r.get("status") != "ok"])
    if strips:
        out.append("\nOpenSCAD's rendering at morph = 0, 0.25, 0.5, 0.75, 1:\n")
        for row, rel in strips:
            out.append("%s (%s)\n\n![%s](%s)\n" % (row["name"], row["note"], row["name"], rel))
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------------

CSV_FIELDS = ["name", "kind", "status", "iou", "iou_a", "iou_b", "own_a", "own_b", "gap_a",
              "gap_b", "solver_iou_a", "solver_iou_b", "primitives", "single", "csg_primitives",
              "middle_pixels", "frames_ok", "same_tree", "trees", "evaluations", "solver_s",
              "stop", "wall_s", "grid_a", "grid_b", "error", "command"]


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", default=os.path.join(REPO_DIR, "build", "bin", "csgfit"))
    ap.add_argument("--bench-dir", default=os.path.join(SHARED_BENCH_DIR, "2d"))
    ap.add_argument("--bench-dir-3d", default=os.path.join(SHARED_BENCH_DIR, "3d", "inversecsg"))
    ap.add_argument("--time", type=float, default=20.0, help="2D budget per run (s)")
    ap.add_argument("--time-3d", type=float, default=60.0, help="3D morph budget (s)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=1, help="runs in parallel (they share the cores)")
    ap.add_argument("--grid", type=int, default=96, help="3D judge: at least grid^3 voxels")
    ap.add_argument("--only", nargs="+", metavar="A", help="only the pairs whose A is one of these")
    ap.add_argument("--no-3d", action="store_true", help="skip the 3D pairs")
    ap.add_argument("--out", default=os.path.join("/tmp", "bench_morph"), help="work files")
    ap.add_argument("--img-dir", default=os.path.join(REPO_DIR, "docs", "img"))
    ap.add_argument("--openscad-timeout", type=float, default=600.0)
    benchlib.add_doc_arg(ap, "morph")
    return ap.parse_args(argv)


def tasks(args):
    """Every run as (kind, item): the 3D morphs first (the longest), then the 2D morphs and
    the own fits of every bitmap they use."""
    pairs2 = [p for p in PAIRS_2D if not args.only or p[0] in args.only]
    pairs3 = [] if args.no_3d else [p for p in PAIRS_3D if not args.only or p[0] in args.only]
    names = list(dict.fromkeys(n for p in pairs2 for n in p[:2]))
    return ([("3d", p) for p in pairs3] + [("2d", p) for p in pairs2]
            + [("own", n) for n in names])


def do_task(args, task):
    """One task; an exception becomes the row's error, so one bad pair never stops the run."""
    kind, item = task
    try:
        if kind == "3d":
            return kind, morph_3d(args, item)
        if kind == "2d":
            return kind, morph_2d(args, item)
        return kind, own_fit(args, item)
    except Exception as exc:
        name = item if kind == "own" else "%s -> %s" % tuple(item[:2])
        row = {"name": name, "kind": kind, "status": "error", "error": str(exc)[:300],
               "a": item[0] if kind != "own" else "", "b": item[1] if kind != "own" else "",
               "note": item[2] if kind == "2d" else ""}
        return kind, ((row, {}) if kind == "2d" else row)


def progress(result):
    kind, res = result
    row = res[0] if kind == "2d" else res
    print("%-4s %-50s %-6s IoU %s %s wall %s %s" % (
        kind, row["name"], row.get("status"), c(row, "iou_a") if kind != "own" else c(row, "iou"),
        c(row, "iou_b") if kind != "own" else "", c(row, "wall_s", 1), row.get("error", "")),
        file=sys.stderr, flush=True)


def main(argv=None):
    args = parse_args(argv)
    if benchlib.missing_cli(PROG, args.cli, "--cli") or benchlib.missing_tool(PROG, "openscad"):
        return 2
    os.makedirs(args.out, exist_ok=True)
    t_start = time.monotonic()
    results = benchlib.run_all(lambda t: do_task(args, t), tasks(args), args.jobs, progress)
    res2d = [res for kind, res in results if kind == "2d"]
    rows2d = [row for row, _ in res2d]
    rows3d = [res for kind, res in results if kind == "3d"]
    own = {res["name"]: res for kind, res in results if kind == "own"}
    attach_own_fits(rows2d, own)
    strips = write_strips(res2d, args)
    text = report(rows2d, own, rows3d, strips, args)
    benchlib.finish(PROG, "morph", "runs", rows2d + rows3d + list(own.values()), CSV_FIELDS,
                    text, args, t_start)
    return 0 if all(ok for _, ok in acceptance(rows2d, rows3d)) else 1


if __name__ == "__main__":
    sys.exit(main())
