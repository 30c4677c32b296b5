#!/usr/bin/python3
"""End-to-end 3D benchmark: csgfit mesh -> .scad -> OpenSCAD STL -> volume IoU, next to InverseCSG.

For every model of ../shared/benchmarks/3d/inversecsg (manifest.json) this takes the input mesh
(CAD models: csg_high_res.off; synthetic models: their ground-truth csg.scad rendered to STL with
OpenSCAD), runs `csgfit mesh IN -o OUT.scad --time T`, renders OUT.scad to STL with OpenSCAD and
scores it against the input by volume IoU on a voxel grid of cubic voxels (at least --grid^3 of
them) over the union of both bounding boxes. The voxelisation is scripts/stl_voxelize.py (ray
parity along z), independent of the solver. InverseCSG's published program for the same model
(inversecsg_solution.scad) is rendered and scored the same way. Writes a per-model CSV and a
Markdown table per kind; what each column means is written down in docs/BENCHMARKS.md.

Renders of the inputs and of InverseCSG's programs are cached in --out (they do not depend on
our solver), so reruns only pay for csgfit and the rendering of our .scad.
Runs on Debian's /usr/bin/python3 with numpy only. A failure on one model is recorded, never
aborts the run; the exit status is 1 if any failed.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import time

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import benchlib  # noqa: E402  (what bench_2d.py does the same way)
import scad_raster  # noqa: E402  (define_args: OpenSCAD -D settings)
import stl_voxelize  # noqa: E402  (scripts/stl_voxelize.py: imported, never copied)
from benchlib import cell, fmt, iou, numeric  # noqa: E402

PROG = "bench_3d"
KIND_LABELS = {"cad": "cad (InverseCSG CAD meshes)",
               "synthetic": "synthetic (ground-truth .scad)"}

# ----------------------------------------------------------------------------------------------
# Meshes and voxels


def read_off(path):
    """Triangles of an OFF mesh as an (n, 3, 3) float64 array; polygons are fanned.

    Line based, as every OFF writer in practice: the header (OFF, optionally with the counts
    on the same line), 'nv nf ne', nv vertex lines, nf face lines 'k i1 .. ik [colour]'."""
    with open(path) as f:
        lines = [l.split("#", 1)[0].split() for l in f]
    lines = [l for l in lines if l]
    if not lines or not lines[0][0].endswith("OFF"):
        raise ValueError("%s: not an OFF file" % path)
    counts = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    body = lines[1:] if len(lines[0]) > 1 else lines[2:]
    nv, nf = int(counts[0]), int(counts[1])
    if len(body) < nv + nf:
        raise ValueError("%s: truncated (%d of %d lines)" % (path, len(body), nv + nf))
    verts = np.array([l[:3] for l in body[:nv]], dtype=np.float64)
    tris = []
    for l in body[nv:nv + nf]:
        k = int(l[0])
        idx = [int(t) for t in l[1:1 + k]]
        for j in range(1, k - 1):
            tris.append((idx[0], idx[j], idx[j + 1]))
    if not tris:
        raise ValueError("%s: no faces" % path)
    return verts[np.array(tris, dtype=np.int64)]


def read_mesh(path):
    if path.lower().endswith(".off"):
        return read_off(path)
    return stl_voxelize.read_stl(path)


def union_grid(tri_sets, grid):
    """Cubic voxels, at least grid^3 of them, over the union of the meshes' bounding boxes
    (padded by one voxel so that no surface lies on the grid's border)."""
    lo = np.min([t.reshape(-1, 3).min(axis=0) for t in tri_sets], axis=0)
    hi = np.max([t.reshape(-1, 3).max(axis=0) for t in tri_sets], axis=0)
    ext = np.maximum(hi - lo, 1e-9)
    ext = np.maximum(ext, ext.max() * 1e-3)  # a flat mesh still gets a grid
    size = float(np.cbrt(np.prod(ext) / float(grid) ** 3))
    n = [int(np.ceil(e / size)) + 2 for e in ext]
    origin = lo - size
    return n, origin, size


def volume_iou(tris_a, tris_b, grid):
    n, origin, size = union_grid([tris_a, tris_b], grid)
    a = stl_voxelize.voxelize(tris_a, n, origin, size) > 0
    b = stl_voxelize.voxelize(tris_b, n, origin, size) > 0
    return iou(a, b), n


# ----------------------------------------------------------------------------------------------
# OpenSCAD and the CLI

SCAD_PRIMITIVE_RE = re.compile(r"\b(cube|sphere|cylinder|polyhedron|rotate_extrude|"
                               r"linear_extrude)\s*\(")
SOLVER_COLUMNS = dict(benchlib.SOLVER_COLUMNS, stop_reason="stop")


def summary_cells(stderr):
    """The solver columns, with the stop reason, from the CLI's summary line."""
    return benchlib.solver_cells(benchlib.parse_summary(stderr), SOLVER_COLUMNS)


def openscad_stl(scad, stl, timeout, defines=None):
    """Renders scad to stl (written atomically so that a killed render is never cached);
    `defines` ({name: value}) are OpenSCAD -D settings (bench_morph.py's frames)."""
    tmp = stl + ".part.stl"
    benchlib.remove_files(tmp)
    cmd = ["openscad"] + scad_raster.define_args(defines) + ["-o", tmp, scad]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        benchlib.remove_files(tmp)
        raise RuntimeError("OpenSCAD did not finish within %g s" % timeout)
    if proc.returncode != 0 or not os.path.exists(tmp) or os.path.getsize(tmp) == 0:
        msg = [l for l in proc.stderr.splitlines() if "ERROR" in l or "WARNING" in l]
        last = (msg or proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        benchlib.remove_files(tmp)
        raise RuntimeError("OpenSCAD exit %d: %s" % (proc.returncode, last[:200]))
    os.replace(tmp, stl)


def cached_stl(scad, stl, timeout):
    """Renders scad once; later runs reuse stl while it is newer than the .scad."""
    if not (os.path.exists(stl) and os.path.getmtime(stl) >= os.path.getmtime(scad)):
        openscad_stl(scad, stl, timeout)
    return stl


# ----------------------------------------------------------------------------------------------
# One model


def prepare_one(entry, args):
    """The model's input mesh (a synthetic model's ground truth is rendered once and cached)."""
    row = {"name": entry["name"], "kind": entry["kind"], "status": "ok", "error": "",
           "gt_primitives": entry.get("gt_primitives") or "", "_errors": []}
    cache = os.path.join(args.out, "cache")
    os.makedirs(cache, exist_ok=True)
    if entry.get("mesh"):
        row["_mesh"] = os.path.join(args.bench_dir, entry["mesh"])
    else:
        row["_mesh"] = cached_stl(os.path.join(args.bench_dir, entry["gt"]),
                                  os.path.join(cache, entry["name"] + ".gt.stl"),
                                  args.openscad_timeout)
    return row


def fit_one(entry, row, args):
    """csgfit mesh on the model; nothing else runs in its time, so --time is what it gets."""
    name = entry["name"]
    scad = os.path.join(args.out, name + ".scad")
    stl = os.path.join(args.out, name + ".stl")
    cmd = benchlib.csgfit_command(args, "mesh", row["_mesh"], scad)
    log = os.path.join(args.out, name + ".stderr.txt")
    wall_file = os.path.join(args.out, name + ".wall.txt")
    if args.reuse and os.path.exists(scad) and os.path.exists(log):
        row["command"] = benchlib.command_text(cmd)
        return reuse_fit(row, log, wall_file)
    benchlib.remove_files(scad, stl, wall_file)
    failure = benchlib.run_cli(cmd, row, scad, log, args.time * 3 + 120, summary_cells,
                               wall_file)
    if failure:
        row["scad_rendered"] = "no"
        row["_errors"].append(failure)
        return row
    if row["solver_primitives"] == "":
        with open(scad) as f:
            row["solver_primitives"] = len(SCAD_PRIMITIVE_RE.findall(f.read()))
    return row


def reuse_fit(row, log, wall_file):
    """Scores a previous run's output again (e.g. with other OpenSCAD settings)."""
    with open(log) as f:
        summary = benchlib.parse_summary(f.read())
    row.update(benchlib.solver_cells(summary, SOLVER_COLUMNS))
    row["exit_code"] = 0
    if os.path.exists(wall_file):
        with open(wall_file) as f:
            row["wall_s"] = float(f.read().strip())
    else:
        row["wall_s"] = summary.get("seconds", 0.0)
        row["wall_from_summary"] = True
    return row


def score_one(entry, row, args):
    """OpenSCAD renders our .scad and InverseCSG's program; both are scored against the input."""
    errors = row.pop("_errors", [])
    target = read_mesh(row.pop("_mesh"))
    row["input_triangles"] = len(target)
    score_inversecsg(entry, row, target, args, errors)
    if row["status"] == "ok":
        score_ours(entry, row, target, args, errors)
    row["error"] = "; ".join(errors)
    return row


def score_inversecsg(entry, row, target, args, errors):
    """InverseCSG's published program for the model, where there is one, scored like ours."""
    sol = entry.get("inversecsg_solution")
    if not (sol and os.path.exists(os.path.join(args.bench_dir, sol))):
        return
    incl = entry.get("inversecsg_primitives_incl_bbox")
    if incl is not None:
        row["icsg_primitives_incl_bbox"] = incl
        row["icsg_primitives"] = incl - 1
    try:
        stl = cached_stl(os.path.join(args.bench_dir, sol),
                         os.path.join(args.out, "cache", entry["name"] + ".inversecsg.stl"),
                         args.openscad_timeout)
        row["icsg_iou"], _ = volume_iou(target, read_mesh(stl), args.grid)
    except Exception as exc:  # recorded, never fatal
        errors.append("InverseCSG: %s" % exc)


def score_ours(entry, row, target, args, errors):
    """OpenSCAD's rendering of our .scad against the input mesh."""
    scad = os.path.join(args.out, entry["name"] + ".scad")
    stl = os.path.join(args.out, entry["name"] + ".stl")
    try:
        openscad_stl(scad, stl, args.openscad_timeout)
        row["scad_rendered"] = "yes"
    except Exception as exc:
        row["scad_rendered"] = "no"
        row["status"] = "openscad-fail"
        errors.append(str(exc))
    if row["scad_rendered"] == "yes":
        try:
            row["iou"], n = volume_iou(target, read_mesh(stl), args.grid)
            row["grid"] = "x".join(map(str, n))
        except Exception as exc:
            row["status"] = "iou-fail"
            errors.append("IoU: %s" % exc)


# ----------------------------------------------------------------------------------------------
# Tables

CSV_FIELDS = ["name", "kind", "status", "iou", "solver_primitives", "wall_s", "stop_reason",
              "icsg_iou", "icsg_primitives", "icsg_primitives_incl_bbox", "gt_primitives",
              "scad_rendered", "solver_iou", "solver_evaluations", "solver_seconds",
              "exit_code", "grid", "input_triangles", "error", "command"]

TARGETS = {"mean_iou": 0.97, "median_wall": 60.0}


def _failed(r):
    return r.get("status") != "ok"


def model_table(rows):
    lines = ["| model | kind | IoU | primitives | seconds | stop reason | InverseCSG IoU | "
             "InverseCSG primitives (excl. / incl. bbox) | GT primitives |",
             "|---|---|--:|--:|--:|---|--:|--:|--:|"]
    for r in rows:
        icsg = "-" if r.get("icsg_primitives") in ("", None) else "%s / %s" % (
            r["icsg_primitives"], r["icsg_primitives_incl_bbox"])
        iou_cell = cell(r, "iou", 4) if not _failed(r) else "%s (%s)" % (
            cell(r, "iou", 4), r["status"])
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["name"], r["kind"], iou_cell, cell(r, "solver_primitives"),
            cell(r, "wall_s", 1), cell(r, "stop_reason"), cell(r, "icsg_iou", 4), icsg,
            cell(r, "gt_primitives")))
    return "\n".join(lines)


def summary_table(rows):
    lines = ["| kind | n | mean IoU | min IoU | mean prims | InverseCSG mean prims (excl. bbox) "
             "| InverseCSG mean IoU | InverseCSG min IoU | GT mean prims | median s | "
             "every .scad rendered | failed |",
             "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|--:|"]
    for label, rs in benchlib.kind_groups(rows, KIND_LABELS) + [("**all**", rows)]:
        ious = numeric(rs, "iou")
        ic = numeric(rs, "icsg_iou")
        rendered = sum(r.get("scad_rendered") == "yes" for r in rs)
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %d |" % (
            label, len(rs), fmt(ious, statistics.mean, 4), fmt(ious, min, 4),
            fmt(numeric(rs, "solver_primitives"), statistics.mean, 1),
            fmt(numeric(rs, "icsg_primitives"), statistics.mean, 1, na="-"),
            fmt(ic, statistics.mean, 4, na="-"), fmt(ic, min, 4, na="-"),
            fmt(numeric(rs, "gt_primitives"), statistics.mean, 1, na="-"),
            fmt(numeric(rs, "wall_s"), statistics.median, 1),
            "%s (%d / %d)" % ("yes" if rendered == len(rs) else "no", rendered, len(rs)),
            sum(_failed(r) for r in rs)))
    return "\n".join(lines)


def acceptance(rows):
    """Issue 4's targets (for a --time 60 run) against this run: list of (text, ok)."""
    ious = numeric(rows, "iou")
    walls = numeric(rows, "wall_s")
    rendered = sum(r.get("scad_rendered") == "yes" for r in rows)
    # Primitives are compared on the models that have an InverseCSG program, without its bbox.
    paired = [r for r in rows if r.get("icsg_primitives") not in ("", None)
              and r.get("solver_primitives") not in ("", None)]
    ours = [float(r["solver_primitives"]) for r in paired]
    theirs = [float(r["icsg_primitives"]) for r in paired]
    n_icsg = sum(r.get("icsg_primitives") not in ("", None) for r in rows)
    checks = [
        ("every .scad renders in OpenSCAD: %d / %d" % (rendered, len(rows)),
         rendered == len(rows)),
        ("mean IoU >= 0.97: %s (%d of %d models rendered)"
         % (fmt(ious, statistics.mean, 4), len(ious), len(rows)),
         len(ious) == len(rows) and statistics.mean(ious) >= TARGETS["mean_iou"]),
        ("fewer primitives than InverseCSG on average: ours %s vs InverseCSG %s excl. bbox "
         "(%d of %d models with an InverseCSG program)"
         % (fmt(ours, statistics.mean, 1), fmt(theirs, statistics.mean, 1), len(paired),
            n_icsg),
         bool(paired) and len(paired) == n_icsg
         and statistics.mean(ours) < statistics.mean(theirs)),
        ("median wall time <= 60 s: %s" % fmt(walls, statistics.median, 1),
         bool(walls) and statistics.median(walls) <= TARGETS["median_wall"]),
    ]
    if not n_icsg:
        checks[2] = ("fewer primitives than InverseCSG on average: n/a (no InverseCSG program "
                     "in this run)", None)
    return checks


def report(rows, args):
    out = [benchlib.measured_line(
        args, "mesh", "%d models" % len(rows), detail="IoU on >= %d^3 voxels, " % args.grid,
        note="" if args.time >= 60 else " The acceptance targets are stated for --time 60.")]
    out.append(summary_table(rows))
    out.append("\nAcceptance targets (issue 4):\n")
    out += benchlib.outcome_lines(acceptance(rows), [r for r in rows if _failed(r)])
    out.append("\nPer model:\n")
    out.append(model_table(rows))
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------------


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    benchlib.add_run_args(ap, "3d", "models", 60.0)
    ap.add_argument("--kind", choices=sorted(KIND_LABELS), help="run only this kind")
    benchlib.add_output_args(ap, "3d")
    ap.add_argument("--reuse", action="store_true",
                    help="score the .scad files a previous run left in --out instead of fitting "
                         "again (models without one are fitted)")
    ap.add_argument("--grid", type=int, default=96,
                    help="IoU grid: cubic voxels, at least GRID^3 of them (default 96)")
    ap.add_argument("--openscad-timeout", type=float, default=300.0,
                    help="seconds per OpenSCAD render (default 300)")
    benchlib.add_doc_arg(ap, "3d")
    return ap.parse_args(argv)


# The stderr line per model: (label, key, format, width) after its name and status.
PROGRESS = [("IoU", "iou", "%.4f", 6), ("prims", "solver_primitives", None, 4),
            ("wall", "wall_s", "%.1f", 6), ("InverseCSG IoU", "icsg_iou", "%.4f", 6),
            ("prims", "icsg_primitives", None, 4)]


def main(argv=None):
    args = parse_args(argv)
    entries, status = benchlib.load_entries(args, PROG, ("models", "entries"), "model")
    if entries is None:
        return status
    if args.kind:
        entries = [e for e in entries if e["kind"] == args.kind]
    if benchlib.missing_tool(PROG, "openscad") or benchlib.missing_cli(PROG, args.cli, "--cli"):
        return 2
    os.makedirs(args.out, exist_ok=True)

    # Three passes, so that OpenSCAD's renders (minutes for a big tree) never share the cores
    # with a timed fit: inputs, then every fit, then every render and score.
    def guarded(fn):
        def run(pair):
            entry, row = pair
            if row is not None and "_mesh" not in row:
                return row  # an earlier pass failed: nothing to go on with
            try:
                return fn(entry, *([] if row is None else [row]), args)
            except Exception as exc:  # a bad model must not abort the run
                return {"name": entry["name"], "kind": entry["kind"], "status": "error",
                        "scad_rendered": "no", "error": str(exc)}
        return run

    t_start = time.monotonic()
    rows = benchlib.run_all(guarded(prepare_one), [(e, None) for e in entries], args.jobs)
    rows = benchlib.run_all(guarded(fit_one), list(zip(entries, rows)), args.jobs)
    rows = benchlib.run_all(guarded(score_one), list(zip(entries, rows)), args.jobs,
                            lambda row: benchlib.print_progress(row, 28, PROGRESS))
    benchlib.finish(PROG, "3d", "models", rows, CSV_FIELDS, report(rows, args), args, t_start)
    return 1 if any(_failed(r) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
