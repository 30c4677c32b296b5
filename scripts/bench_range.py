#!/usr/bin/python3
"""Range-image benchmark: csgfit range -> .scad -> OpenSCAD STL -> seen again by the same sensor.

For every model of ../shared/benchmarks/range (manifest.json: 27 models, three 192 x 192 range
images each: view A orthographic, view A orthographic with noise, view B pinhole) this runs
`csgfit range IMG -o OUT.scad --time T --seed S`, renders OUT.scad with OpenSCAD, rasterises the
STL through the image's own sidecar camera (scripts/range_judge.py, not the solver's renderer)
and compares depth and silhouette with the input; then the volume IoU against the whole
ground-truth solid. Each model's views A and B are also given together in one call. The
primitive count is read from OpenSCAD's flattened .csg of the result. object_b's precedence
graph (the solver's OUT.json) is checked against Lin & Chen's Fig. 10.

--gt-as-result {exact,shifted,scaled} judges the ground truth itself (or a copy moved by 2 % of
its diagonal, or scaled by 1.05) instead of running csgfit: the test of the judge. Renders of the
ground truths are cached in --out/cache. A failure on one run is recorded, never aborts the run;
the exit status is 1 if any failed.
"""

import argparse
import json
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import bench_3d  # noqa: E402  (its OpenSCAD render and cache)
import benchlib  # noqa: E402
import range_judge as rj  # noqa: E402
from benchlib import cell, fmt, numeric  # noqa: E402

PROG = "bench_range"
SENSORS = ("ortho", "ortho_noisy", "pinhole")
TWO_VIEW = "two_view"
TWO_VIEW_SENSORS = ("ortho", "pinhole")  # view A and view B, the noiseless A
TARGETS = {"silhouette_iou": 0.98, "depth_err_pct": 0.5, "volume_iou_one": 0.95,
           "volume_iou_two": 0.98, "prim_ratio": 1.5, "median_wall": 20.0}

# ----------------------------------------------------------------------------------------------
# Runs: one per (model, sensor) and one per model with both views


def image_of(entry, sensor):
    """The manifest's image of `sensor` (NAME_<sensor>.png)."""
    want = "%s_%s.png" % (entry["name"], sensor)
    return next(i for i in entry["images"] if i == want)


def plan_runs(entries, args):
    """The runs of the selection: dicts with name, model, sensor and the input images."""
    runs = []
    for e in entries:
        for s in args.sensors:
            runs.append({"name": "%s_%s" % (e["name"], s), "model": e["name"], "sensor": s,
                         "inputs": [image_of(e, s)]})
        if args.two_view:
            runs.append({"name": "%s_%s" % (e["name"], TWO_VIEW), "model": e["name"],
                         "sensor": TWO_VIEW,
                         "inputs": [image_of(e, s) for s in TWO_VIEW_SENSORS]})
    return runs


def range_command(args, inputs, out_path):
    return ([args.cli, "range"] + [os.path.join(args.bench_dir, i) for i in inputs]
            + ["-o", out_path, "--time", "%g" % args.time, "--seed", str(args.seed)]
            + shlex.split(args.extra_args))


def new_row(run, entry):
    return {"name": run["name"], "model": run["model"], "sensor": run["sensor"],
            "inputs": " ".join(run["inputs"]), "status": "ok", "error": "",
            "gt_primitives": entry.get("gt_primitives", ""), "_errors": []}


def fit_one(run, entry, args):
    """csgfit range on the run's images into --out/NAME.scad (timed, nothing else running)."""
    row = new_row(run, entry)
    scad = os.path.join(args.out, run["name"] + ".scad")
    if args.gt_as_result:
        write_gt_copy(os.path.join(args.bench_dir, entry["gt"]), scad, args.gt_as_result)
        row.update(exit_code=0, wall_s=0.0, command="(ground truth, %s)" % args.gt_as_result)
        return row
    log = os.path.join(args.out, run["name"] + ".stderr.txt")
    benchlib.remove_files(scad, os.path.join(args.out, run["name"] + ".stl"))
    failure = benchlib.run_cli(range_command(args, run["inputs"], scad), row, scad, log,
                               args.time * 3 + 120, summary_line)
    if failure:
        row["scad_rendered"] = "no"
        row["_errors"].append(failure)
    return row


def summary_line(stderr):
    """The CLI's last stderr line, kept for the reader only: nothing is scored from it."""
    lines = stderr.strip().splitlines()
    return {"solver_summary": lines[-1].strip()[:300] if lines else ""}


def write_gt_copy(gt_scad, scad, how):
    """The ground truth as a "result": itself, or moved / scaled so that the judge must notice.
    The move is 2 % of the diagonal along x; the scale 1.05 about the box centre."""
    if how == "exact":
        shutil.copyfile(gt_scad, scad)
        return
    tris = rj.read_stl(gt_stl_path(gt_scad))
    lo, hi = tris.reshape(-1, 3).min(axis=0), tris.reshape(-1, 3).max(axis=0)
    c = (lo + hi) / 2
    if how == "shifted":
        wrap = "translate([%r, 0, 0])" % (0.02 * float(np.linalg.norm(hi - lo)))
    else:
        wrap = "translate(%s) scale(1.05) translate(%s)" % (list(c), list(-c))
    with open(gt_scad) as f:
        body = f.read()
    with open(scad, "w") as f:
        f.write("// %s copy of %s\n%s {\n%s\n}\n" % (how, gt_scad, wrap, body))


CACHE = {"dir": None}


def gt_stl_path(gt_scad):
    return os.path.join(CACHE["dir"], os.path.basename(gt_scad)[:-len(".scad")] + ".stl")


def gt_stl(entry, args):
    """The ground truth rendered once (kept in --out/cache while newer than its .scad)."""
    gt_scad = os.path.join(args.bench_dir, entry["gt"])
    return bench_3d.cached_stl(gt_scad, gt_stl_path(gt_scad), args.openscad_timeout)


def render_gt(entry, args):
    """gt_stl, a failure said on stderr: the model's rows then fail one by one when scored."""
    try:
        gt_stl(entry, args)
    except Exception as exc:
        print("%s: %s: ground truth: %s" % (PROG, entry["name"], exc), file=sys.stderr)


def openscad_csg(scad, csg, timeout):
    """OpenSCAD's flattened .csg of `scad` (fast: no CGAL), for the primitive count."""
    proc = subprocess.run(["openscad", "-o", csg, scad], capture_output=True, text=True,
                          timeout=timeout)
    if proc.returncode != 0 or not os.path.exists(csg):
        raise RuntimeError("OpenSCAD .csg exit %d" % proc.returncode)
    with open(csg) as f:
        return rj.count_primitives(f.read())


# ----------------------------------------------------------------------------------------------
# Scoring


def score_one(row, entry, args):
    """Renders the run's .scad, counts its primitives and scores it view by view and by volume."""
    errors = ([row["error"]] if row.get("error") else []) + row.pop("_errors", [])
    if row["status"] == "ok":
        try:
            score_result(row, entry, args)
        except Exception as exc:  # recorded, never fatal
            row["status"] = row["status"] if row["status"] != "ok" else "score-fail"
            errors.append(str(exc))
    row["error"] = "; ".join(errors)
    return row


def score_result(row, entry, args):
    scad = os.path.join(args.out, row["name"] + ".scad")
    stl = os.path.join(args.out, row["name"] + ".stl")
    try:
        if args.gt_as_result == "exact":
            shutil.copyfile(gt_stl(entry, args), stl)  # the same render: no need to pay twice
        else:
            bench_3d.openscad_stl(scad, stl, args.openscad_timeout)
        row["scad_rendered"] = "yes"
    except Exception:
        row["scad_rendered"], row["status"] = "no", "openscad-fail"
        raise
    row["primitives"] = openscad_csg(scad, os.path.join(args.out, row["name"] + ".csg"),
                                     args.openscad_timeout)
    if row["gt_primitives"]:
        row["prim_ratio"] = row["primitives"] / float(row["gt_primitives"])
    gt = rj.read_stl(gt_stl(entry, args))
    result = rj.read_stl(stl)
    diagonal = rj.bbox_diagonal(gt)
    views = {}
    for image in row["inputs"].split():
        views[image] = score_view(os.path.join(args.bench_dir, image), result, diagonal)
    row["_views"] = views
    keys = ("silhouette_iou", "depth_err_pct", "depth_err_median_pct", "depth_err_p95_pct")
    for key in keys:
        vals = [v[key] for v in views.values() if key in v]
        if vals:
            row[key] = float(np.mean(vals))
    if row["sensor"] == TWO_VIEW:
        for tag, image in zip("AB", row["inputs"].split()):
            row["silhouette_iou_" + tag] = views[image]["silhouette_iou"]
            row["depth_err_pct_" + tag] = views[image].get("depth_err_pct", "")
    row["volume_iou"] = rj.volume_iou(result, gt, args.grid)


def score_view(image, result_tris, diagonal):
    cam = rj.load_camera(image)
    return rj.view_metrics(rj.read_depth(image, cam), rj.render_depth(result_tris, cam),
                           diagonal)


# ----------------------------------------------------------------------------------------------
# object_b


def object_b_check(args):
    """Fits object_b's view A to JSON and checks its precedence graph: [(item, ok, detail)]."""
    out_json = os.path.join(args.out, "object_b_graph.json")
    if args.gt_as_result:
        return [("precedence graph", None, "not available (--gt-as-result runs no solver)")]
    row = {}
    benchlib.remove_files(out_json)
    failure = benchlib.run_cli(range_command(args, ["object_b_ortho.png"], out_json), row,
                               out_json, os.path.join(args.out, "object_b_graph.stderr.txt"),
                               args.time * 3 + 120, lambda err: {})
    if failure and not os.path.exists(out_json):
        return [("precedence graph", False, "csgfit failed: %s" % failure)]
    try:
        with open(out_json) as f:
            doc = json.load(f)
    except (OSError, ValueError) as exc:
        return [("precedence graph", False, "unreadable JSON: %s" % exc)]
    return rj.object_b_checks(doc)


def object_b_lines(checks):
    mark = lambda ok: "n/a" if ok is None else ("PASS" if ok else "FAIL")
    return ["- %s: %s (%s)" % (mark(ok), item, detail) for item, ok, detail in checks]


# ----------------------------------------------------------------------------------------------
# Tables and the report


def _failed(r):
    return r.get("status") != "ok"


def one_view(rows):
    return [r for r in rows if r["sensor"] != TWO_VIEW]


def two_view(rows):
    return [r for r in rows if r["sensor"] == TWO_VIEW]


def scored(rows, key):
    """The rows' values of `key`, a run that rendered nothing counting 0 (IoUs) so that a
    failure can never raise a mean."""
    return [float(r[key]) if r.get(key, "") not in ("", None) else 0.0 for r in rows]


def image_table(rows):
    lines = ["| run | sensor | status | silhouette IoU | depth error % (mean / median) | "
             "volume IoU | primitives (GT) | seconds |", "|---|---|---|--:|--:|--:|--:|--:|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s | %s / %s | %s | %s (%s) | %s |" % (
            r["model"], r["sensor"], r["status"], cell(r, "silhouette_iou", 4),
            cell(r, "depth_err_pct", 3), cell(r, "depth_err_median_pct", 3),
            cell(r, "volume_iou", 4), cell(r, "primitives"), cell(r, "gt_primitives"),
            cell(r, "wall_s", 1)))
    return "\n".join(lines)


def model_table(rows):
    head = " | ".join("volume IoU %s" % s for s in SENSORS + (TWO_VIEW,))
    lines = ["| model | GT primitives | mean silhouette IoU | mean depth error %% | %s | "
             "mean primitives |" % head, "|---|--:|--:|--:|" + "--:|" * (len(SENSORS) + 2)]
    for model in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == model]
        by = {r["sensor"]: r for r in rs}
        one = one_view(rs)
        lines.append("| %s | %s | %s | %s | %s | %s |" % (
            model, cell(rs[0], "gt_primitives"),
            fmt(numeric(one, "silhouette_iou"), statistics.mean, 4, "-"),
            fmt(numeric(one, "depth_err_pct"), statistics.mean, 3, "-"),
            " | ".join(cell(by.get(s, {}), "volume_iou", 4) for s in SENSORS + (TWO_VIEW,)),
            fmt(numeric(rs, "primitives"), statistics.mean, 1, "-")))
    return "\n".join(lines)


def aggregates(rows):
    one, two = one_view(rows), two_view(rows)
    rendered = sum(r.get("scad_rendered") == "yes" for r in rows)
    sens = {s: [r for r in rows if r["sensor"] == s] for s in SENSORS + (TWO_VIEW,)}
    return {
        "runs": len(rows), "rendered": rendered, "images": len(one), "two_view_runs": len(two),
        "silhouette_iou_mean": _mean(scored(one, "silhouette_iou")),
        "depth_err_pct_mean": _mean(numeric(one, "depth_err_pct")),
        "volume_iou_one_view_mean": _mean(scored(one, "volume_iou")),
        "volume_iou_two_view_mean": _mean(scored(two, "volume_iou")),
        "prim_ratio_mean": _mean(numeric(one, "prim_ratio")),
        "prim_ratio_two_view_mean": _mean(numeric(two, "prim_ratio")),
        "median_wall_s": _median(numeric(one, "wall_s")),
        "per_sensor": {s: {"silhouette_iou_mean": _mean(scored(rs, "silhouette_iou")),
                           "depth_err_pct_mean": _mean(numeric(rs, "depth_err_pct")),
                           "volume_iou_mean": _mean(scored(rs, "volume_iou")),
                           "median_wall_s": _median(numeric(rs, "wall_s"))}
                       for s, rs in sens.items() if rs}}


def _mean(vals):
    return float(statistics.mean(vals)) if vals else None


def _median(vals):
    return float(statistics.median(vals)) if vals else None


def _show(v, digits):
    return "n/a" if v is None else "%.*f" % (digits, v)


def acceptance(agg):
    t = TARGETS
    at = lambda key, target, below: (None if agg[key] is None else
                                     (agg[key] <= target if below else agg[key] >= target))
    return [
        ("every run writes a .scad that renders: %d / %d" % (agg["rendered"], agg["runs"]),
         agg["rendered"] == agg["runs"]),
        ("silhouette IoU mean >= %.2f: %s" % (t["silhouette_iou"],
                                              _show(agg["silhouette_iou_mean"], 4)),
         at("silhouette_iou_mean", t["silhouette_iou"], False)),
        ("mean depth error <= %.1f %% of the diagonal: %s" % (
            t["depth_err_pct"], _show(agg["depth_err_pct_mean"], 3)),
         at("depth_err_pct_mean", t["depth_err_pct"], True)),
        ("volume IoU mean, one view >= %.2f: %s" % (
            t["volume_iou_one"], _show(agg["volume_iou_one_view_mean"], 4)),
         at("volume_iou_one_view_mean", t["volume_iou_one"], False)),
        ("volume IoU mean, two views >= %.2f: %s" % (
            t["volume_iou_two"], _show(agg["volume_iou_two_view_mean"], 4)),
         at("volume_iou_two_view_mean", t["volume_iou_two"], False)),
        ("primitives / GT primitives mean <= %.1f: %s (two views: %s)" % (
            t["prim_ratio"], _show(agg["prim_ratio_mean"], 2),
            _show(agg["prim_ratio_two_view_mean"], 2)),
         at("prim_ratio_mean", t["prim_ratio"], True)),
        ("median time per image <= %g s: %s" % (t["median_wall"], _show(agg["median_wall_s"], 1)),
         at("median_wall_s", t["median_wall"], True)),
    ]


def report(rows, agg, b_checks, pictures, args):
    what = ("the ground truth as the result (%s)" % args.gt_as_result if args.gt_as_result
            else None)
    out = [benchlib.measured_line(
        args, "range", "%d images + %d two-view runs" % (agg["images"], agg["two_view_runs"]),
        detail="volume IoU on >= %d^3 voxels, " % args.grid,
        note=(" Judged: %s, no solver run." % what) if what else "")]
    out.append("| sensor | n | silhouette IoU | depth error % | volume IoU | median s |")
    out.append("|---|--:|--:|--:|--:|--:|")
    for s, a in agg["per_sensor"].items():
        n = sum(r["sensor"] == s for r in rows)
        out.append("| %s | %d | %s | %s | %s | %s |" % (
            s, n, _show(a["silhouette_iou_mean"], 4), _show(a["depth_err_pct_mean"], 3),
            _show(a["volume_iou_mean"], 4), _show(a["median_wall_s"], 1)))
    out.append("\n(two_view: views A and B in one call; its silhouette and depth are those of "
               "its two views, averaged. The silhouette, depth, primitive and time targets are "
               "over the one-view runs.)")
    out.append("\nAcceptance targets (issue 10):\n")
    out += benchlib.outcome_lines(acceptance(agg), [r for r in rows if _failed(r)])
    if b_checks:
        out.append("\nobject_b's precedence graph (`csgfit range object_b_ortho.png -o .json`):\n")
        out += object_b_lines(b_checks)
    if pictures:
        out.append("\nInput depth | result depth seen by the same sensor | error (red: result "
                   "too far, blue: too near, full at 1 % of the diagonal; yellow: missed, "
                   "green: extra):\n")
        out += ["![%s](%s)" % (name, rel) for name, rel in pictures]
    out.append("\nPer model:\n")
    out.append(model_table(rows))
    out.append("\n<details><summary>Per run</summary>\n")
    out.append(image_table(rows))
    out.append("\n</details>")
    return "\n".join(out) + "\n"


def save_pictures(rows, entries, args, count=4):
    """Strips for object_b and the worst-scoring other runs (by silhouette then depth), written
    under images/range/ next to the doc (stale strips removed): [(name, relative path)]."""
    image_dir = os.path.join(os.path.dirname(os.path.abspath(args.write_doc)), "images", "range")
    os.makedirs(image_dir, exist_ok=True)
    for f in os.listdir(image_dir):
        if f.endswith(".png"):
            os.remove(os.path.join(image_dir, f))
    ok = [r for r in one_view(rows) if r.get("scad_rendered") == "yes" and "_views" in r]
    worst = sorted(ok, key=lambda r: (r["silhouette_iou"], -r.get("depth_err_pct", 0)))
    chosen = [r for r in ok if r["name"] == "object_b_ortho"]
    chosen += [r for r in worst if r not in chosen][:count - len(chosen)]
    by_name = {e["name"]: e for e in entries}
    out = []
    for r in chosen:
        image = os.path.join(args.bench_dir, r["inputs"])
        cam = rj.load_camera(image)
        result = rj.render_depth(rj.read_stl(os.path.join(args.out, r["name"] + ".stl")), cam)
        diagonal = rj.bbox_diagonal(rj.read_stl(gt_stl(by_name[r["model"]], args)))
        path = os.path.join(image_dir, r["name"] + ".png")
        rj.save_strip(path, rj.read_depth(image, cam), result, diagonal)
        out.append((r["name"], os.path.relpath(path, os.path.dirname(os.path.abspath(args.write_doc)))))
    return out


# ----------------------------------------------------------------------------------------------


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    benchlib.add_run_args(ap, "range", "models", 20.0)
    ap.add_argument("--models", nargs="+", dest="only", metavar="NAME",
                    help="run only these models (the same as --only)")
    ap.add_argument("--sensors", nargs="+", choices=SENSORS, default=list(SENSORS))
    ap.add_argument("--no-two-view", dest="two_view", action="store_false",
                    help="skip the runs with views A and B together")
    ap.add_argument("--object-b", dest="object_b", action="store_true", default=None,
                    help="check object_b's precedence graph (default: when object_b is run)")
    ap.add_argument("--no-object-b", dest="object_b", action="store_false")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--gt-as-result", choices=("exact", "shifted", "scaled"),
                    help="judge the ground truth (or a moved / scaled copy), run no solver")
    ap.add_argument("--grid", type=int, default=128,
                    help="volume IoU grid: cubic voxels, at least GRID^3 (default 128)")
    ap.add_argument("--openscad-timeout", type=float, default=600.0)
    ap.add_argument("--cache", help="where the ground truths' renders are kept (default "
                                    "OUT/cache)")
    benchlib.add_output_args(ap, "range")
    benchlib.add_doc_arg(ap, "range")
    return ap.parse_args(argv)


PROGRESS = [("sil", "silhouette_iou", "%.4f", 6), ("depth%", "depth_err_pct", "%.3f", 6),
            ("vol", "volume_iou", "%.4f", 6), ("prims", "primitives", None, 3),
            ("wall", "wall_s", "%.1f", 5)]
CSV_FIELDS = ["name", "model", "sensor", "status", "silhouette_iou", "depth_err_pct",
              "depth_err_median_pct", "depth_err_p95_pct", "volume_iou", "primitives",
              "gt_primitives", "prim_ratio", "wall_s", "exit_code", "scad_rendered",
              "silhouette_iou_A", "depth_err_pct_A", "silhouette_iou_B", "depth_err_pct_B",
              "inputs", "solver_summary", "error", "command"]


def guarded(fn, entry_of):
    """fn(item, entry) with any exception recorded in a failed row instead of raised."""
    def run(item):
        try:
            return fn(item, entry_of[item["model"]])
        except Exception as exc:
            inputs = item.get("inputs", "")
            return {"name": item["name"], "model": item["model"], "sensor": item["sensor"],
                    "inputs": inputs if isinstance(inputs, str) else " ".join(inputs),
                    "status": "error", "scad_rendered": "no", "error": str(exc), "_errors": []}
    return run


def main(argv=None):
    args = parse_args(argv)
    entries, status = benchlib.load_entries(args, PROG, ("models",), "model")
    if entries is None:
        return status
    if benchlib.missing_tool(PROG, "openscad") or (
            not args.gt_as_result and benchlib.missing_cli(PROG, args.cli, "--cli")):
        return 2
    args.out = os.path.abspath(args.out)  # OpenSCAD's -o must not depend on its cwd
    os.makedirs(args.out, exist_ok=True)
    CACHE["dir"] = os.path.abspath(args.cache or os.path.join(args.out, "cache"))
    os.makedirs(CACHE["dir"], exist_ok=True)
    entry_of = {e["name"]: e for e in entries}
    t_start = time.monotonic()
    # Ground truths first, fits next, renders and scores last, so that no OpenSCAD render
    # shares the cores with a timed fit.
    benchlib.run_all(lambda e: render_gt(e, args), entries, args.jobs)
    runs = plan_runs(entries, args)
    rows = benchlib.run_all(guarded(lambda run, e: fit_one(run, e, args), entry_of), runs,
                            args.jobs)
    rows = benchlib.run_all(guarded(lambda row, e: score_one(row, e, args), entry_of), rows,
                            args.jobs, lambda row: benchlib.print_progress(row, 30, PROGRESS))
    check_b = args.object_b if args.object_b is not None else "object_b" in entry_of
    b_checks = object_b_check(args) if check_b else []
    for line in object_b_lines(b_checks):
        print("object_b " + line[2:], file=sys.stderr)
    agg = aggregates(rows)
    pictures = save_pictures(rows, entries, args) if args.write_doc else []
    write_json(rows, agg, b_checks, args)
    benchlib.finish(PROG, "range", "runs", rows, CSV_FIELDS,
                    report(rows, agg, b_checks, pictures, args), args, t_start)
    return 1 if any(_failed(r) for r in rows) else 0


def write_json(rows, agg, b_checks, args):
    """--out/results.json: every number of the run, per view too."""
    doc = {"args": {k: v for k, v in vars(args).items()}, "aggregates": agg,
           "acceptance": [{"item": t, "ok": ok} for t, ok in acceptance(agg)],
           "object_b": [{"item": i, "ok": ok, "detail": d} for i, ok, d in b_checks],
           "runs": [dict({k: v for k, v in r.items() if not k.startswith("_")},
                         views=r.get("_views", {})) for r in rows]}
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
