#!/usr/bin/python3
"""Point-cloud benchmark: csgfit points -> .scad / .json / .step -> OpenSCAD, our B-splines, FreeCAD.

For every cloud of ../shared/benchmarks/points (manifest.json: crosses, cube_minus_sphere and
boss_and_pocket, each scanned from the top and all around; the blade, 192 points and a dense
scan; each as .xyz and .ply) this runs `csgfit points IN -o OUT.scad -o OUT.json -o OUT.step
--time T --seed S` and judges the result with OpenSCAD and code of its own, never the solver's:

- CSG models: OUT.scad and the ground truth NAME.gt.scad rendered to STL by OpenSCAD, volume
  IoU on one grid of at least 128^3 voxels (range_judge / stl_voxelize), primitives counted in
  OpenSCAD's flattened .csg of the result. A top scan's solid is everything between z = 0 and
  the scanned surface; the ground truths stand on z = 0 without undercuts, so it is the whole
  ground-truth solid.
- The blade: the true surface (blade.gt.json) against the nurbs leaf of OUT.json, both evaluated
  by scripts/points_judge.py, along z on a 200 x 60 grid; OUT.step opened in FreeCAD (one valid
  solid with a B-spline face); OUT.scad rendered, its header's deviation read, its top seen from
  above against the true surface.
- A table on a subset (all CSG clouds as .xyz and blade_top): `--islands 1` and `--search hill`
  next to the default run, same budget and seed.

--gt-as-result {exact,shifted,scaled} judges the ground truth (or a copy moved by 2 % of its
diagonal / raised by 0.05 mm, or scaled by 1.05 / heights by 1.01) instead of running csgfit:
the test of the judge. OpenSCAD renders are cached (--cache) by the text of the .scad. A failure
on one run is recorded, never aborts the run; the exit status is 1 if any failed.
"""

import argparse
import hashlib
import json
import os
import shlex
import shutil
import statistics
import sys
import time

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import bench_3d  # noqa: E402  (its OpenSCAD render)
import bench_range  # noqa: E402  (the ground truths' cache, their moved copies, the .csg count)
import benchlib  # noqa: E402
import points_judge as pj  # noqa: E402
import range_judge as rj  # noqa: E402
from benchlib import cell, fmt, numeric  # noqa: E402

PROG = "bench_points"
TARGETS = {"volume_iou_mean": 0.98, "volume_iou_min": 0.95, "prim_ratio": 1.5,
           "dev_mean": 0.01, "dev_max": 0.06}
# The comparison's variants: extra csgfit options; the default run is the first column.
VARIANTS = {"default": [], "islands1": ["--islands", "1"], "hill": ["--search", "hill"]}
VARIANT_LABELS = {"default": "GP/ES, default islands", "islands1": "GP/ES, --islands 1",
                  "hill": "--search hill"}
SAMPLES = (200, 60)  # the true surface's samples over its x-y rectangle
DOC_HEADING = "## Point clouds (seed 004)"
BEGIN, END = "<!-- benchpoints:begin -->", "<!-- benchpoints:end -->"

# ----------------------------------------------------------------------------------------------
# Runs


def is_blade(entry):
    """A free-form model: its ground truth is a B-spline patch (.json), not a .scad."""
    return entry["gt"].endswith(".json")


def new_run(entry, form, variant):
    suffix = "" if variant == "default" else "_" + variant
    return {"name": "%s_%s%s" % (entry["name"], form, suffix), "model": entry["name"],
            "kind": "blade" if is_blade(entry) else "csg", "scan": entry.get("scan", ""),
            "format": form, "variant": variant, "input": "%s.%s" % (entry["name"], form)}


def compare_models(entries, args):
    """The comparison's clouds: --compare-models, else every CSG cloud and blade_top."""
    if args.compare_models:
        return [e for e in entries if e["name"] in set(args.compare_models)]
    return [e for e in entries if not is_blade(e) or e["name"] == "blade_top"]


def plan_runs(entries, args):
    """Every cloud in every format, then the comparison's other variants (one format)."""
    runs = [new_run(e, f, "default") for e in entries for f in args.formats]
    if args.compare and not args.gt_as_result:
        form = "xyz" if "xyz" in args.formats else args.formats[0]
        runs += [new_run(e, form, v) for e in compare_models(entries, args)
                 for v in VARIANTS if v != "default"]
    return runs


def outputs(args, name):
    """The files of one run in --out."""
    base = os.path.join(args.out, name)
    return {ext: base + "." + ext for ext in ("scad", "json", "step", "csg")} | {
        "log": base + ".stderr.txt"}


def points_command(args, run, out):
    return ([args.cli, "points", os.path.join(args.bench_dir, run["input"]), "-o", out["scad"],
             "-o", out["json"], "-o", out["step"], "--time", "%g" % args.time,
             "--seed", str(args.seed)] + VARIANTS[run["variant"]] + shlex.split(args.extra_args))


def fit_one(run, entry, args):
    """csgfit points on one cloud (timed, nothing else running), or the ground truth written
    in its place."""
    row = dict(run, status="ok", error="", gt_primitives=entry.get("gt_primitives") or "",
               _errors=[])
    out = outputs(args, run["name"])
    benchlib.remove_files(*out.values())  # a stale output must never be judged
    if args.gt_as_result:
        write_gt_result(entry, out, args)
        row.update(exit_code=0, wall_s=0.0, command="(ground truth, %s)" % args.gt_as_result)
        return row
    failure = benchlib.run_cli(points_command(args, run, out), row, out["scad"], out["log"],
                               args.time * 3 + 120, bench_range.summary_line)
    if failure:
        row["scad_rendered"] = "no"
        row["_errors"].append(failure)
    return row


def write_gt_result(entry, out, args):
    """The ground truth as a result: a CSG model's .scad (bench_range's copies); the blade's
    patch as the contract's JSON leaf, our polyhedron .scad and a STEP built by FreeCAD."""
    gt = os.path.join(args.bench_dir, entry["gt"])
    if not is_blade(entry):
        bench_range.write_gt_copy(gt, out["scad"], args.gt_as_result)
        return
    with open(gt) as f:
        leaf = pj.gt_as_leaf(json.load(f), args.gt_as_result)
    with open(out["json"], "w") as f:
        json.dump(pj.result_document(leaf, entry["name"]), f, indent=1)
    with open(out["scad"], "w") as f:
        f.write(pj.polyhedron_scad(pj.patch_from_leaf(leaf)))
    pj.write_step(out["json"], out["step"], args.freecad_timeout)


# ----------------------------------------------------------------------------------------------
# Renders: ground truths once, results by the text of their .scad


def cached_render(scad, args):
    """OpenSCAD's STL of `scad`, kept in the cache under a hash of its text, so that the same
    program (a ground-truth copy judged four times, a rerun) is rendered once."""
    with open(scad, "rb") as f:
        key = hashlib.sha1(f.read()).hexdigest()[:20]
    stl = os.path.join(bench_range.CACHE["dir"], "scad-%s.stl" % key)
    if not os.path.exists(stl):
        bench_3d.openscad_stl(scad, stl, args.openscad_timeout)
    return stl


def render_gt(entry, args):
    """The CSG ground truth rendered once (bench_range's cache, newer than its .scad) and filed
    under its hash too, so that the exact copy of --gt-as-result costs no second render."""
    if is_blade(entry):
        return
    bench_range.render_gt(entry, args)
    gt_scad = os.path.join(args.bench_dir, entry["gt"])
    with open(gt_scad, "rb") as f:
        key = hashlib.sha1(f.read()).hexdigest()[:20]
    linked = os.path.join(bench_range.CACHE["dir"], "scad-%s.stl" % key)
    stl = bench_range.gt_stl_path(gt_scad)
    if os.path.exists(stl) and not os.path.exists(linked):
        shutil.copyfile(stl, linked)


def render_result(row, out, args):
    """The run's .scad rendered (a failed render is a failed run) and its primitives counted
    in OpenSCAD's flattened .csg."""
    try:
        stl = cached_render(out["scad"], args)
        row["scad_rendered"] = "yes"
    except Exception:
        row["scad_rendered"], row["status"] = "no", "openscad-fail"
        raise
    row["primitives"] = bench_range.openscad_csg(out["scad"], out["csg"], args.openscad_timeout)
    if row["gt_primitives"]:
        row["prim_ratio"] = row["primitives"] / float(row["gt_primitives"])
    return rj.read_stl(stl)


# ----------------------------------------------------------------------------------------------
# Scoring


def score_one(row, entry, args):
    """Every check of the run's kind; each failure is recorded and the next check still runs."""
    errors = ([row["error"]] if row.get("error") else []) + row.pop("_errors", [])
    checks = [score_csg] if row["kind"] == "csg" else [score_surface, score_step, score_scad]
    if row["status"] == "ok":
        for check in checks:
            try:
                check(row, entry, args)
            except Exception as exc:  # recorded, never fatal
                row["status"] = row["status"] if row["status"] != "ok" else "score-fail"
                errors.append("%s: %s" % (check.__name__, exc))
    row["error"] = "; ".join(errors)
    return row


def score_csg(row, entry, args):
    result = render_result(row, outputs(args, row["name"]), args)
    gt = rj.read_stl(bench_range.gt_stl(entry, args))
    row["volume_iou"] = rj.volume_iou(result, gt, args.grid)


def gt_patch(entry, args):
    with open(os.path.join(args.bench_dir, entry["gt"])) as f:
        return pj.patch_from_gt(json.load(f))


def score_surface(row, entry, args):
    """The true surface against the JSON's nurbs leaves, along z."""
    with open(outputs(args, row["name"])["json"]) as f:
        leaves = pj.nurbs_leaves(json.load(f))
    row["nurbs_leaves"] = len(leaves)
    if not leaves:
        raise ValueError("no {\"type\": \"nurbs\"} leaf in the JSON")
    row.update(pj.deviation(gt_patch(entry, args), [pj.patch_from_leaf(l) for l in leaves],
                            SAMPLES))


def score_step(row, entry, args):
    """FreeCAD opens the STEP: exactly one valid solid with a B-spline face passes."""
    step = outputs(args, row["name"])["step"]
    row["step_ok"] = False
    if not os.path.exists(step):
        raise FileNotFoundError("no .step written")
    chk = pj.step_check(step, args.freecad_timeout)
    row.update(step_ok=chk["passed"], step_solids=chk["solids"], step_valid=chk["valid"],
               step_bspline=chk["bspline_face"], step_volume=chk["mesh_volume"])
    if row.get("true_volume"):
        row["step_volume_ratio"] = chk["mesh_volume"] / row["true_volume"]


def score_scad(row, entry, args):
    """The blade's .scad renders; its header's deviation is read, and its top, seen from
    above, is measured against the true surface."""
    out = outputs(args, row["name"])
    result = render_result(row, out, args)
    with open(out["scad"]) as f:
        reported = pj.header_deviations(f.read())
    row["scad_header_dev"] = max(reported.values()) if reported else "none"
    row.update(pj.top_deviation(result, gt_patch(entry, args)))


def guarded(fn, entry_of):
    """fn(row, entry) with any exception recorded in a failed row instead of raised."""
    def run(item):
        try:
            return fn(item, entry_of[item["model"]])
        except Exception as exc:
            return dict({k: v for k, v in item.items() if not k.startswith("_")},
                        status="error", scad_rendered="no", error=str(exc))
    return run


# ----------------------------------------------------------------------------------------------
# Aggregates and acceptance


def _failed(r):
    return r.get("status") != "ok"


def picked(rows, kind, variant="default"):
    return [r for r in rows if r["kind"] == kind and r["variant"] == variant]


def worst(rows, key):
    """The largest value of `key`, a run without one counting infinite; None without runs."""
    vals = [float(r[key]) if r.get(key, "") not in ("", None) else float("inf") for r in rows]
    return max(vals) if vals else None


def aggregates(rows):
    csg, blade = picked(rows, "csg"), picked(rows, "blade")
    ious = bench_range.scored(csg, "volume_iou")
    return {"runs": len(rows), "csg_runs": len(csg), "blade_runs": len(blade),
            "csg_rendered": sum(r.get("scad_rendered") == "yes" for r in csg),
            "blade_rendered": sum(r.get("scad_rendered") == "yes" for r in blade),
            "volume_iou_mean": bench_range._mean(ious),
            "volume_iou_min": min(ious) if ious else None,
            "prim_ratio_mean": bench_range._mean(numeric(csg, "prim_ratio")),
            "dev_mean_worst": worst(blade, "dev_mean"), "dev_max_worst": worst(blade, "dev_max"),
            "step_passed": sum(r.get("step_ok") is True for r in blade),
            "median_wall_s": bench_range._median(numeric(picked(rows, "csg") + blade,
                                                         "wall_s"))}


def acceptance(agg):
    t, show = TARGETS, bench_range._show
    at = lambda key, target, below: (None if agg[key] is None else
                                     (agg[key] <= target if below else agg[key] >= target))
    csg, blade = agg["csg_runs"], agg["blade_runs"]
    return [
        ("every CSG .scad renders: %d / %d" % (agg["csg_rendered"], csg),
         agg["csg_rendered"] == csg if csg else None),
        ("CSG volume IoU mean >= %.2f: %s" % (t["volume_iou_mean"],
                                             show(agg["volume_iou_mean"], 4)),
         at("volume_iou_mean", t["volume_iou_mean"], False)),
        ("CSG volume IoU min >= %.2f: %s" % (t["volume_iou_min"], show(agg["volume_iou_min"], 4)),
         at("volume_iou_min", t["volume_iou_min"], False)),
        ("primitives / GT primitives mean <= %.1f: %s" % (t["prim_ratio"],
                                                         show(agg["prim_ratio_mean"], 2)),
         at("prim_ratio_mean", t["prim_ratio"], True)),
        ("blade: true surface within %.2f mm of the fit on average (worst run): %s mm"
         % (t["dev_mean"], show(agg["dev_mean_worst"], 4)), at("dev_mean_worst", t["dev_mean"],
                                                                True)),
        ("blade: true surface within %.2f mm of the fit at most (worst run): %s mm"
         % (t["dev_max"], show(agg["dev_max_worst"], 4)), at("dev_max_worst", t["dev_max"], True)),
        ("blade STEP opens in FreeCAD as one valid solid with a B-spline face: %d / %d"
         % (agg["step_passed"], blade), agg["step_passed"] == blade if blade else None),
        ("every blade .scad renders: %d / %d" % (agg["blade_rendered"], blade),
         agg["blade_rendered"] == blade if blade else None),
    ]


# ----------------------------------------------------------------------------------------------
# Tables and the report


def csg_table(rows):
    lines = ["| run | scan | format | status | volume IoU | primitives (GT) | seconds |",
             "|---|---|---|---|--:|--:|--:|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s | %s | %s (%s) | %s |" % (
            r["model"], r["scan"], r["format"], r["status"], cell(r, "volume_iou", 4),
            cell(r, "primitives"), cell(r, "gt_primitives"), cell(r, "wall_s", 1)))
    return "\n".join(lines)


def step_cell(r):
    if "step_solids" not in r:
        return "-"
    return "%s: %s solid(s), %s, %s" % (
        "pass" if r["step_ok"] else "FAIL", r["step_solids"],
        "valid" if r["step_valid"] else "invalid",
        "B-spline face" if r["step_bspline"] else "no B-spline face")


def blade_table(rows):
    lines = ["| run | status | deviation mean / max mm | outside | STEP | STEP volume / true | "
             ".scad header mm | .scad top mean / max mm | seconds |",
             "|---|---|--:|--:|---|--:|--:|--:|--:|"]
    for r in rows:
        lines.append("| %s | %s | %s / %s | %s | %s | %s | %s | %s / %s | %s |" % (
            r["name"], r["status"], cell(r, "dev_mean", 4), cell(r, "dev_max", 4),
            cell(r, "outside"), step_cell(r), cell(r, "step_volume_ratio", 4),
            cell(r, "scad_header_dev"), cell(r, "scad_top_dev_mean", 4),
            cell(r, "scad_top_dev_max", 4), cell(r, "wall_s", 1)))
    return "\n".join(lines)


def measure_cell(r):
    """A comparison cell: volume IoU, or the blade's deviation mean / max in mm."""
    if r is None:
        return "-"
    if r["kind"] == "blade":
        return "%s / %s mm" % (cell(r, "dev_mean", 4), cell(r, "dev_max", 4))
    return cell(r, "volume_iou", 4)


def compare_table(rows):
    """Per cloud of the comparison, each variant's measure, primitives and seconds; then the
    CSG clouds' means per variant."""
    others = [r for r in rows if r["variant"] != "default"]
    if not others:
        return None
    names = list(dict.fromkeys(r["name"][:-len(r["variant"]) - 1] for r in others))
    by = {(r["name"], r["variant"]): r for r in rows}
    head = " | ".join("%s: IoU or deviation | prims | s" % VARIANT_LABELS[v] for v in VARIANTS)
    lines = ["| cloud | %s |" % head, "|---|" + "--:|" * (3 * len(VARIANTS))]
    for name in names:
        got = [by.get((name if v == "default" else "%s_%s" % (name, v), v)) for v in VARIANTS]
        lines.append("| %s | %s |" % (name, " | ".join(
            "%s | %s | %s" % (measure_cell(r), cell(r or {}, "primitives"),
                              cell(r or {}, "wall_s", 1)) for r in got)))
    means = []
    for v in VARIANTS:
        rs = [by[(n if v == "default" else "%s_%s" % (n, v), v)] for n in names
              if (n if v == "default" else "%s_%s" % (n, v), v) in by]
        csg = [r for r in rs if r["kind"] == "csg"]
        means.append("%s | %s | %s" % (fmt(bench_range.scored(csg, "volume_iou"),
                                           statistics.mean, 4, "-"),
                                       fmt(numeric(csg, "primitives"), statistics.mean, 1, "-"),
                                       fmt(numeric(csg, "wall_s"), statistics.mean, 1, "-")))
    lines.append("| **CSG mean** | %s |" % " | ".join(means))
    return "\n".join(lines)


def report(rows, agg, args):
    what = ("the ground truth as the result (%s)" % args.gt_as_result if args.gt_as_result
            else None)
    out = [benchlib.measured_line(
        args, "points --seed %d" % args.seed, "%d runs" % agg["runs"],
        detail="volume IoU on >= %d^3 voxels, blade deviation on %d x %d samples, "
               % (args.grid, SAMPLES[0], SAMPLES[1]),
        note=(" Judged: %s, no solver run." % what) if what else "")]
    out.append("Acceptance targets (issue 14, at `--time 30`):\n")
    out += benchlib.outcome_lines(acceptance(agg), [r for r in rows if _failed(r)])
    out.append("\nCSG models (OpenSCAD's rendering of the .scad against the ground-truth "
               "solid; primitives in its flattened .csg):\n")
    out.append(csg_table(picked(rows, "csg")))
    out.append("\nThe blade (the true B-spline surface against the JSON's nurbs leaf along z; "
               "STEP read by FreeCAD, its volume from a 0.005 mm tessellation; the .scad's top "
               "seen from above at 0.2 mm pixels against the true surface):\n")
    out.append(blade_table(picked(rows, "blade")))
    table = compare_table(rows)
    if table:
        out.append("\nIslands against one population, GP/ES against the hill climbing (same "
                   "`--time` and seed; blade: deviation mean / max):\n")
        out.append(table)
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------------


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    benchlib.add_run_args(ap, "points", "clouds", 30.0)
    ap.add_argument("--models", nargs="+", dest="only", metavar="NAME",
                    help="run only these clouds (the same as --only)")
    ap.add_argument("--formats", nargs="+", choices=("xyz", "ply"), default=["xyz", "ply"])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-compare", dest="compare", action="store_false",
                    help="skip the --islands 1 and --search hill runs")
    ap.add_argument("--compare-models", nargs="+", metavar="NAME",
                    help="the comparison's clouds (default: every CSG cloud and blade_top)")
    ap.add_argument("--gt-as-result", choices=("exact", "shifted", "scaled"),
                    help="judge the ground truth (or a moved / scaled copy), run no solver")
    ap.add_argument("--grid", type=int, default=128,
                    help="volume IoU grid: cubic voxels, at least GRID^3 (default 128)")
    ap.add_argument("--openscad-timeout", type=float, default=600.0)
    ap.add_argument("--freecad-timeout", type=float, default=300.0)
    ap.add_argument("--cache", help="where OpenSCAD's renders are kept (default OUT/cache)")
    benchlib.add_output_args(ap, "points")
    benchlib.add_doc_arg(ap, "points")
    return ap.parse_args(argv)


PROGRESS = [("vol", "volume_iou", "%.4f", 6), ("dev", "dev_mean", "%.4f", 6),
            ("max", "dev_max", "%.4f", 6), ("prims", "primitives", None, 3),
            ("step", "step_ok", None, 5), ("wall", "wall_s", "%.1f", 5)]
CSV_FIELDS = ["name", "model", "kind", "scan", "format", "variant", "status", "volume_iou",
              "primitives", "gt_primitives", "prim_ratio", "dev_mean", "dev_max", "dev_p95",
              "outside", "samples", "nurbs_leaves", "step_ok", "step_solids", "step_valid",
              "step_bspline", "step_volume", "step_volume_ratio", "true_volume",
              "scad_header_dev", "scad_top_dev_mean", "scad_top_dev_max", "scad_rendered",
              "wall_s", "exit_code", "solver_summary", "error", "command"]


def ensure_section(path):
    """Appends the heading and the markers to the doc when it has none yet."""
    with open(path) as f:
        doc = f.read()
    if BEGIN not in doc:
        with open(path, "a") as f:
            f.write("\n%s\n\n%s\n%s\n" % (DOC_HEADING, BEGIN, END))


def write_json(rows, agg, args):
    """--out/results.json: every number of the run."""
    doc = {"args": vars(args), "aggregates": agg,
           "acceptance": [{"item": t, "ok": ok} for t, ok in acceptance(agg)],
           "runs": [{k: v for k, v in r.items() if not k.startswith("_")} for r in rows]}
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(doc, f, indent=1)


def main(argv=None):
    args = parse_args(argv)
    entries, status = benchlib.load_entries(args, PROG, ("models",), "cloud")
    if entries is None:
        return status
    if (benchlib.missing_tool(PROG, "openscad")
            or (any(map(is_blade, entries)) and benchlib.missing_tool(PROG, "freecadcmd"))
            or (not args.gt_as_result and benchlib.missing_cli(PROG, args.cli, "--cli"))):
        return 2
    args.out = os.path.abspath(args.out)  # OpenSCAD's -o must not depend on its cwd
    os.makedirs(args.out, exist_ok=True)
    bench_range.CACHE["dir"] = os.path.abspath(args.cache or os.path.join(args.out, "cache"))
    os.makedirs(bench_range.CACHE["dir"], exist_ok=True)
    entry_of = {e["name"]: e for e in entries}
    t_start = time.monotonic()
    # Ground truths first, fits next, renders and scores last, so that no OpenSCAD render or
    # FreeCAD check shares the cores with a timed fit.
    benchlib.run_all(lambda e: render_gt(e, args), entries, args.jobs)
    rows = benchlib.run_all(guarded(lambda run, e: fit_one(run, e, args), entry_of),
                            plan_runs(entries, args), args.jobs)
    rows = benchlib.run_all(guarded(lambda row, e: score_one(row, e, args), entry_of), rows,
                            args.jobs, lambda row: benchlib.print_progress(row, 34, PROGRESS))
    agg = aggregates(rows)
    write_json(rows, agg, args)
    if args.write_doc:
        ensure_section(args.write_doc)
    benchlib.finish(PROG, "points", "runs", rows, CSV_FIELDS, report(rows, agg, args), args,
                    t_start)
    return 1 if any(_failed(r) for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
