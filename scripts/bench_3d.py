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
import concurrent.futures
import csv
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(SCRIPT_DIR)
DEFAULT_BENCH_DIR = os.path.normpath(os.path.join(REPO_DIR, "..", "shared", "benchmarks", "3d",
                                                  "inversecsg"))
DOC_BEGIN = "<!-- bench3d:begin -->"
DOC_END = "<!-- bench3d:end -->"

KIND_LABELS = {"cad": "cad (InverseCSG CAD meshes)",
               "synthetic": "synthetic (ground-truth .scad)"}

if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import stl_voxelize  # noqa: E402  (scripts/stl_voxelize.py: imported, never copied)

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
    union = np.count_nonzero(a | b)
    return (1.0 if union == 0 else np.count_nonzero(a & b) / union), n


# ----------------------------------------------------------------------------------------------
# OpenSCAD and the CLI

SUMMARY_RE = re.compile(r"IoU\s*[=:]?\s*(?P<iou>[0-9.]+)")
PRIMS_RE = re.compile(r"(?P<n>\d+)\s+primitives?")
EVALS_RE = re.compile(r"(?P<n>\d+)\s+evaluations?")
SECONDS_RE = re.compile(r"(?P<s>[0-9.]+)\s*s\b")
STOP_RE = re.compile(r"\(([^()]*)\)\s*$")
SCAD_PRIMITIVE_RE = re.compile(r"\b(cube|sphere|cylinder|polyhedron|rotate_extrude|"
                               r"linear_extrude)\s*\(")


def parse_summary(stderr):
    """The CLI's final line: 'csgfit: IoU 0.98, 12 primitives, 340 trees, 34567 evaluations,
    29.93 s (time)'; returns the keys it found."""
    out = {}
    lines = [l for l in stderr.splitlines() if SUMMARY_RE.search(l) and PRIMS_RE.search(l)]
    if lines:
        line = lines[-1].strip()
        out["iou"] = float(SUMMARY_RE.search(line).group("iou"))
        out["primitives"] = int(PRIMS_RE.search(line).group("n"))
        if EVALS_RE.search(line):
            out["evaluations"] = int(EVALS_RE.search(line).group("n"))
        secs = SECONDS_RE.findall(line.split("evaluations")[-1])
        if secs:
            out["seconds"] = float(secs[-1])
        stop = STOP_RE.search(line)
        if stop:
            out["stop"] = stop.group(1).strip()
    return out


def openscad_stl(scad, stl, timeout):
    """Renders scad to stl (written atomically so that a killed render is never cached)."""
    tmp = stl + ".part.stl"
    if os.path.exists(tmp):
        os.remove(tmp)
    try:
        proc = subprocess.run(["openscad", "-o", tmp, scad], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise RuntimeError("OpenSCAD did not finish within %g s" % timeout)
    if proc.returncode != 0 or not os.path.exists(tmp) or os.path.getsize(tmp) == 0:
        msg = [l for l in proc.stderr.splitlines() if "ERROR" in l or "WARNING" in l]
        last = (msg or proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        if os.path.exists(tmp):
            os.remove(tmp)
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
    cmd = [args.cli, "mesh", row["_mesh"], "-o", scad, "--time", "%g" % args.time]
    cmd += shlex.split(args.extra_args)
    row["command"] = " ".join(shlex.quote(c) for c in cmd)
    log = os.path.join(args.out, name + ".stderr.txt")
    wall_file = os.path.join(args.out, name + ".wall.txt")
    if args.reuse and os.path.exists(scad) and os.path.exists(log):
        # Score a previous run's output again (e.g. with other OpenSCAD settings).
        with open(log) as f:
            summary = parse_summary(f.read())
        row["solver_iou"] = summary.get("iou", "")
        row["solver_primitives"] = summary.get("primitives", "")
        row["solver_evaluations"] = summary.get("evaluations", "")
        row["solver_seconds"] = summary.get("seconds", "")
        row["stop_reason"] = summary.get("stop", "")
        row["exit_code"] = 0
        if os.path.exists(wall_file):
            with open(wall_file) as f:
                row["wall_s"] = float(f.read().strip())
        else:
            row["wall_s"] = summary.get("seconds", 0.0)
            row["wall_from_summary"] = True
        return row
    for stale in (scad, stl, wall_file):
        if os.path.exists(stale):
            os.remove(stale)
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True,
                              timeout=args.time * 3 + 120)
        row["wall_s"] = time.monotonic() - t0
        row["exit_code"] = proc.returncode
        with open(log, "w") as f:
            f.write(proc.stderr)
        with open(wall_file, "w") as f:
            f.write("%.3f\n" % row["wall_s"])
        if proc.returncode != 0:
            last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
            raise RuntimeError("csgfit exit %d: %s" % (proc.returncode, last[:200]))
        summary = parse_summary(proc.stderr)
        row["solver_iou"] = summary.get("iou", "")
        row["solver_primitives"] = summary.get("primitives", "")
        row["solver_evaluations"] = summary.get("evaluations", "")
        row["solver_seconds"] = summary.get("seconds", "")
        row["stop_reason"] = summary.get("stop", "")
        if not os.path.exists(scad):
            raise RuntimeError("csgfit exited 0 but wrote no .scad")
    except subprocess.TimeoutExpired:
        row["wall_s"] = time.monotonic() - t0
        row["status"] = "cli-timeout"
        row["scad_rendered"] = "no"
        row["_errors"].append("csgfit did not finish")
        return row
    except Exception as exc:
        row["status"] = "cli-fail"
        row["scad_rendered"] = "no"
        row["_errors"].append(str(exc))
        return row
    if row["solver_primitives"] == "":
        with open(scad) as f:
            row["solver_primitives"] = len(SCAD_PRIMITIVE_RE.findall(f.read()))
    return row


def score_one(entry, row, args):
    """OpenSCAD renders our .scad and InverseCSG's program; both are scored against the input."""
    name = entry["name"]
    errors = row.pop("_errors", [])
    target = read_mesh(row.pop("_mesh"))
    row["input_triangles"] = len(target)
    sol = entry.get("inversecsg_solution")
    if sol and os.path.exists(os.path.join(args.bench_dir, sol)):
        incl = entry.get("inversecsg_primitives_incl_bbox")
        if incl is not None:
            row["icsg_primitives_incl_bbox"] = incl
            row["icsg_primitives"] = incl - 1
        try:
            stl = cached_stl(os.path.join(args.bench_dir, sol),
                             os.path.join(args.out, "cache", name + ".inversecsg.stl"),
                             args.openscad_timeout)
            row["icsg_iou"], _ = volume_iou(target, read_mesh(stl), args.grid)
        except Exception as exc:  # recorded, never fatal
            errors.append("InverseCSG: %s" % exc)
    if row["status"] == "ok":
        scad = os.path.join(args.out, name + ".scad")
        stl = os.path.join(args.out, name + ".stl")
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
    row["error"] = "; ".join(errors)
    return row


# ----------------------------------------------------------------------------------------------
# Tables

CSV_FIELDS = ["name", "kind", "status", "iou", "solver_primitives", "wall_s", "stop_reason",
              "icsg_iou", "icsg_primitives", "icsg_primitives_incl_bbox", "gt_primitives",
              "scad_rendered", "solver_iou", "solver_evaluations", "solver_seconds",
              "exit_code", "grid", "input_triangles", "error", "command"]

TARGETS = {"mean_iou": 0.97, "median_wall": 60.0}


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


def _cell(r, key, digits=None):
    v = r.get(key, "")
    if v in ("", None):
        return "-"
    return ("%.*f" % (digits, float(v))) if digits is not None else str(v)


def _failed(r):
    return r.get("status") != "ok"


def kind_groups(rows):
    groups = {}
    for r in rows:
        groups.setdefault(r["kind"], []).append(r)
    order = [k for k in KIND_LABELS if k in groups] + [k for k in groups if k not in KIND_LABELS]
    return [(KIND_LABELS.get(k, k), groups[k]) for k in order] + [("**all**", rows)]


def model_table(rows):
    lines = ["| model | kind | IoU | primitives | seconds | stop reason | InverseCSG IoU | "
             "InverseCSG primitives (excl. / incl. bbox) | GT primitives |",
             "|---|---|--:|--:|--:|---|--:|--:|--:|"]
    for r in rows:
        icsg = "-" if r.get("icsg_primitives") in ("", None) else "%s / %s" % (
            r["icsg_primitives"], r["icsg_primitives_incl_bbox"])
        iou_cell = _cell(r, "iou", 4) if not _failed(r) else "%s (%s)" % (
            _cell(r, "iou", 4), r["status"])
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["name"], r["kind"], iou_cell, _cell(r, "solver_primitives"),
            _cell(r, "wall_s", 1), _cell(r, "stop_reason"), _cell(r, "icsg_iou", 4), icsg,
            _cell(r, "gt_primitives")))
    return "\n".join(lines)


def summary_table(rows):
    lines = ["| kind | n | mean IoU | min IoU | mean prims | InverseCSG mean prims (excl. bbox) "
             "| InverseCSG mean IoU | InverseCSG min IoU | GT mean prims | median s | "
             "every .scad rendered | failed |",
             "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|--:|"]
    for label, rs in kind_groups(rows):
        ious = _num(rs, "iou")
        ic = _num(rs, "icsg_iou")
        rendered = sum(r.get("scad_rendered") == "yes" for r in rs)
        lines.append("| %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %d |" % (
            label, len(rs), _fmt(ious, statistics.mean, 4), _fmt(ious, min, 4),
            _fmt(_num(rs, "solver_primitives"), statistics.mean, 1),
            _fmt(_num(rs, "icsg_primitives"), statistics.mean, 1, na="-"),
            _fmt(ic, statistics.mean, 4, na="-"), _fmt(ic, min, 4, na="-"),
            _fmt(_num(rs, "gt_primitives"), statistics.mean, 1, na="-"),
            _fmt(_num(rs, "wall_s"), statistics.median, 1),
            "%s (%d / %d)" % ("yes" if rendered == len(rs) else "no", rendered, len(rs)),
            sum(_failed(r) for r in rs)))
    return "\n".join(lines)


def acceptance(rows):
    """Issue 4's targets (for a --time 60 run) against this run: list of (text, ok)."""
    ious = _num(rows, "iou")
    walls = _num(rows, "wall_s")
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
         % (_fmt(ious, statistics.mean, 4), len(ious), len(rows)),
         len(ious) == len(rows) and statistics.mean(ious) >= TARGETS["mean_iou"]),
        ("fewer primitives than InverseCSG on average: ours %s vs InverseCSG %s excl. bbox "
         "(%d of %d models with an InverseCSG program)"
         % (_fmt(ours, statistics.mean, 1), _fmt(theirs, statistics.mean, 1), len(paired),
            n_icsg),
         bool(paired) and len(paired) == n_icsg
         and statistics.mean(ours) < statistics.mean(theirs)),
        ("median wall time <= 60 s: %s" % _fmt(walls, statistics.median, 1),
         bool(walls) and statistics.median(walls) <= TARGETS["median_wall"]),
    ]
    if not n_icsg:
        checks[2] = ("fewer primitives than InverseCSG on average: n/a (no InverseCSG program "
                     "in this run)", None)
    return checks


def git_commit():
    try:
        return subprocess.run(["git", "-C", REPO_DIR, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip() or "?"
    except (OSError, subprocess.SubprocessError):
        return "?"


def report(rows, args):
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    extra = (" " + args.extra_args) if args.extra_args else ""
    out = ["Measured %s, commit %s, `csgfit mesh --time %g%s`, %d models, --jobs %d, IoU on "
           ">= %d^3 voxels, %d cores (%s).%s\n" % (
               when, git_commit(), args.time, extra, len(rows), args.jobs, args.grid,
               os.cpu_count() or 0, platform.platform(terse=True),
               "" if args.time >= 60 else
               " The acceptance targets are stated for --time 60.")]
    out.append(summary_table(rows))
    out.append("\nAcceptance targets (issue 4):\n")
    for text, ok in acceptance(rows):
        mark = "n/a" if ok is None else ("PASS" if ok else "FAIL")
        out.append("- %s: %s" % (mark, text))
    failed = [r for r in rows if _failed(r)]
    if failed:
        out.append("\nFailures:\n")
        for r in failed:
            out.append("- `%s`: %s (%s)" % (r["name"], r["status"], r.get("error", "")))
    out.append("\nPer model:\n")
    out.append(model_table(rows))
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
    ap.add_argument("--time", type=float, default=60.0, help="csgfit --time budget (s)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="models in parallel (default 1: the solver uses every core itself)")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="run only these models")
    ap.add_argument("--kind", choices=sorted(KIND_LABELS), help="run only this kind")
    ap.add_argument("--out", default=os.path.join(REPO_DIR, "bench-out", "3d"))
    ap.add_argument("--extra-args", default="", help="appended to every csgfit command")
    ap.add_argument("--reuse", action="store_true",
                    help="score the .scad files a previous run left in --out instead of fitting "
                         "again (models without one are fitted)")
    ap.add_argument("--grid", type=int, default=96,
                    help="IoU grid: cubic voxels, at least GRID^3 of them (default 96)")
    ap.add_argument("--openscad-timeout", type=float, default=300.0,
                    help="seconds per OpenSCAD render (default 300)")
    ap.add_argument("--write-doc", nargs="?", const=os.path.join(REPO_DIR, "docs",
                                                                 "BENCHMARKS.md"),
                    metavar="MD", help="replace the bench3d section of docs/BENCHMARKS.md")
    args = ap.parse_args(argv)

    manifest = os.path.join(args.bench_dir, "manifest.json")
    if not os.path.exists(manifest):
        print("bench_3d: %s not found: skipped" % manifest)
        return 0
    with open(manifest) as f:
        entries = json.load(f)
    if isinstance(entries, dict):
        entries = entries.get("models") or entries.get("entries") or []
    if args.only:
        unknown = set(args.only) - {e["name"] for e in entries}
        if unknown:
            print("bench_3d: unknown model(s): %s" % " ".join(sorted(unknown)), file=sys.stderr)
            return 2
        entries = [e for e in entries if e["name"] in set(args.only)]
    if args.kind:
        entries = [e for e in entries if e["kind"] == args.kind]
    if shutil.which("openscad") is None:
        print("bench_3d: openscad not found (apt-get install openscad)", file=sys.stderr)
        return 2
    if not (os.path.isfile(args.cli) and os.access(args.cli, os.X_OK)):
        print("bench_3d: CLI %s not found (build it, or pass --cli)" % args.cli,
              file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)

    # Three passes, so that OpenSCAD's renders (minutes for a big tree) never share the cores
    # with a timed fit: inputs, then every fit, then every render and score.
    def guarded(fn, entry, *rest):
        try:
            return fn(entry, *rest, args)
        except Exception as exc:  # a bad model must not abort the run
            return {"name": entry["name"], "kind": entry["kind"], "status": "error",
                    "scad_rendered": "no", "error": str(exc)}

    t_start = time.monotonic()
    workers = max(1, args.jobs)
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        prepared = list(pool.map(lambda e: guarded(prepare_one, e), entries))
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        fitted = list(pool.map(lambda er: er[1] if "_mesh" not in er[1] else guarded(fit_one, *er),
                               zip(entries, prepared)))
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(lambda er: er[1] if "_mesh" not in er[1] else guarded(score_one, *er),
                               (e, r)): e["name"] for e, r in zip(entries, fitted)}
        for fut in concurrent.futures.as_completed(futures):
            row = fut.result()
            results[row["name"]] = row
            print("%-28s %-13s IoU %-6s prims %-4s wall %-6s InverseCSG IoU %-6s prims %-4s %s" % (
                row["name"], row["status"],
                "%.4f" % row["iou"] if "iou" in row else "-",
                row.get("solver_primitives", "-"),
                "%.1f" % row["wall_s"] if "wall_s" in row else "-",
                "%.4f" % row["icsg_iou"] if "icsg_iou" in row else "-",
                row.get("icsg_primitives", "-"), row.get("error", "")),
                file=sys.stderr, flush=True)
    rows = [results[e["name"]] for e in entries]

    csv_path = os.path.join(args.out, "results.csv")
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow({k: ("%.6g" % v if isinstance(v, float) else v)
                             for k, v in r.items()})

    text = report(rows, args)
    print(text)
    print("bench_3d: %d models in %.0f s; results in %s" % (
        len(rows), time.monotonic() - t_start, csv_path), file=sys.stderr)
    if args.write_doc:
        write_doc(args.write_doc, text)
        print("bench_3d: updated %s" % args.write_doc, file=sys.stderr)
    return 1 if any(_failed(r) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
