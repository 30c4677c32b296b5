#!/usr/bin/python3
"""CSG-tree optimisation benchmark (seed 001): inflate real programs, optimise, prove it's the same solid.

For every OpenSCAD program of ../shared/benchmarks/3d/inversecsg (the ground-truth csg.scad of the
synthetic and CAD models, and InverseCSG's published inversecsg_solution.scad), this
  1. flattens it with OpenSCAD (`openscad -o P.csg P.scad`): the reference program;
  2. optimises it as it is (`csgfit optimize P.csg -o P.opt.csg`): it must never grow;
  3. for --seeds seeds: inflates it with seed 001's generator (`csgfit inflate P.csg --steps 10
     --seed S`, CSI / DNI / DLI / ALI equally likely) and optimises the inflated program;
  4. judges every optimised program with OpenSCAD and code of its own, never the solver's: the
     program's size is counted here on OpenSCAD's flattening of it (primitives plus boolean
     operations with two or more operands), and the solid is OpenSCAD's rendering to STL,
     voxelised by scripts/stl_voxelize.py on a grid of at least --grid^3 cubic voxels and compared
     by IoU with the rendering of the reference.

Writes results.csv and a Markdown report (docs/BENCHMARKS.md between <!-- benchopt:begin/end -->
with --write-doc). Runs on Debian's /usr/bin/python3 with numpy only.
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
if SCRIPT_DIR not in sys.path:
    sys.path.insert(0, SCRIPT_DIR)
import benchlib  # noqa: E402
import stl_voxelize  # noqa: E402
from bench_3d import openscad_stl, volume_iou  # noqa: E402

PROG = "bench_optimize"
REPO = os.path.dirname(SCRIPT_DIR)
DEFAULT_DATA = os.path.join(REPO, "..", "shared", "benchmarks", "3d", "inversecsg")
CALL_RE = re.compile(r'"(?:[^"\\]|\\.)*"|[A-Za-z_$][A-Za-z0-9_$]*|[(){};]|[^\s(){};"A-Za-z_$]+')
OPERATIONS = {"union", "difference", "intersection", "group", "multmatrix", "color", "render"}
EXTRUSIONS = {"linear_extrude", "rotate_extrude"}


def program_size(csg_text):
    """(primitives, operations) of a flattened program: every call that is not a grouping or
    transform is a primitive (an extrusion with its 2D children counts once); an operation is
    a boolean (or an implicit union) with two or more operands."""
    tokens = CALL_RE.findall(csg_text)
    stack, prims, ops, i = [[None, 0]], 0, 0, 0

    def close():
        nonlocal ops
        name, count = stack.pop()
        if name in OPERATIONS and count >= 2 and name not in ("multmatrix", "color", "render"):
            ops += 1
        elif name in ("multmatrix", "color", "render") and count >= 2:
            ops += 1  # several children under a transform: an implicit union
    while i < len(tokens):
        t = tokens[i]
        if t == "}":
            close()
            i += 1
            continue
        if re.match(r"[A-Za-z_$]", t) and i + 1 < len(tokens) and tokens[i + 1] == "(":
            depth, j = 0, i + 1
            while j < len(tokens):
                depth += tokens[j] == "("
                depth -= tokens[j] == ")"
                j += 1
                if depth == 0:
                    break
            opens = j < len(tokens) and tokens[j] == "{"
            if t in OPERATIONS:
                stack[-1][1] += 1
                if opens:
                    stack.append([t, 0])
            else:
                if stack[-1][0] != "_extrusion":
                    stack[-1][1] += 1
                    prims += 1
                if opens:
                    stack.append(["_extrusion", 0])
            i = j + 1
            continue
        i += 1
    while len(stack) > 1:
        close()
    return prims, ops


def run(cmd, timeout):
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise RuntimeError("%s: exit %d: %s" % (os.path.basename(cmd[0]) + " " + cmd[1], proc.returncode,
                                                (proc.stderr.strip().splitlines() or ["?"])[-1][:200]))
    return proc, time.monotonic() - t0


def flatten(scad, csg, timeout):
    if not (os.path.exists(csg) and os.path.getmtime(csg) >= os.path.getmtime(scad)):
        run(["openscad", "-o", csg, scad], timeout)
    return csg


def reference_stl(csg, stl, timeout):
    if not os.path.exists(stl):
        openscad_stl(csg, stl, timeout)
    return stl


def judge(row, ref_stl, out_csg, args, tag):
    """Size of out_csg as OpenSCAD flattens it, and its rendering's IoU with the reference."""
    flat = out_csg + ".flat.csg"
    run(["openscad", "-o", flat, out_csg], args.timeout)
    with open(flat) as f:
        prims, ops = program_size(f.read())
    row[tag + "_size"] = prims + ops
    row[tag + "_primitives"] = prims
    stl = out_csg + ".stl"
    openscad_stl(out_csg, stl, args.timeout)
    value, _ = volume_iou(stl_voxelize.read_stl(ref_stl), stl_voxelize.read_stl(stl), args.grid)
    row[tag + "_iou"] = value


def optimise(row, src, out, args, tag):
    proc, seconds = run([args.cli, "optimize", src, "-o", out, "--quiet", "--seed", "1"] + args.extra, args.timeout)
    row[tag + "_seconds"] = seconds


def compare_methods(row, src, base, ref, args):
    """Each --methods remaining-solid optimiser on the same inflated program: time, size, IoU."""
    for method in args.methods:
        out = "%s.%s.csg" % (base, method)
        tag = "m_" + method
        try:
            proc, seconds = run([args.cli, "optimize", src, "-o", out, "--quiet", "--method", method], args.timeout)
            row[tag + "_seconds"] = seconds
            judge(row, ref, out, args, tag)
        except Exception as e:  # noqa: BLE001
            row[tag + "_error"] = str(e)
            row["status"], row["error"] = "failed", "%s: %s" % (method, e)


def one(entry, args):
    name, program, scad = entry
    base = os.path.join(args.out, name + "." + program)
    rows = []
    try:
        csg = flatten(scad, base + ".csg", args.timeout)
        with open(csg) as f:
            prims, ops = program_size(f.read())
        ref = reference_stl(csg, base + ".stl", args.timeout)
    except Exception as e:  # noqa: BLE001  (recorded, the run goes on)
        return [{"name": name, "program": program, "run": "-", "status": "reference failed", "error": str(e)}]
    for seed in [0] + list(range(1, args.seeds + 1)):
        row = {"name": name, "program": program, "run": "as is" if seed == 0 else "inflated %d" % seed,
               "size": prims + ops, "primitives": prims, "status": "ok"}
        try:
            src = csg
            if seed:
                src = "%s.infl%d.csg" % (base, seed)
                run([args.cli, "inflate", csg, "-o", src, "--steps", str(args.steps), "--seed", str(seed), "-q"],
                    args.timeout)
                with open(src) as f:
                    p2, o2 = program_size(f.read())
                row["inflated_size"] = p2 + o2
            out = "%s.opt%d.csg" % (base, seed)
            optimise(row, src, out, args, "opt")
            judge(row, ref, out, args, "opt")
            if row["opt_iou"] < 0.999:
                row["status"] = "different solid"
            if seed == 1:
                compare_methods(row, src, base, ref, args)
        except Exception as e:  # noqa: BLE001
            row["status"], row["error"] = "failed", str(e)
        rows.append(row)
    return rows


def entries(args):
    with open(os.path.join(args.data, "manifest.json")) as f:
        manifest = json.load(f)
    out = []
    for m in manifest["models"]:
        for key, program in (("gt", "gt"), ("inversecsg_solution", "inversecsg")):
            if m.get(key) and program in args.programs:
                out.append((m["name"], program, os.path.join(args.data, m[key])))
    if args.only:
        out = [e for e in out if e[0] in args.only]
    return out


def ratio(r):
    return r["opt_size"] / r["size"]


def report(rows, args):
    ok = [r for r in rows if "opt_iou" in r]
    inflated = [r for r in ok if r["run"] != "as is"]
    as_is = [r for r in ok if r["run"] == "as is"]
    failed = [r for r in rows if r["status"] != "ok"]
    lines = ["Measured %s, commit %s, `csgfit inflate --steps %d` then `csgfit optimize%s`, %d programs, "
             "%d runs, --jobs %d, %d cores." % (benchlib.now(), benchlib.git_commit(), args.steps,
                                                 (" " + " ".join(args.extra)) if args.extra else "",
                                                 len({(r["name"], r["program"]) for r in rows}), len(rows),
                                                 args.jobs, os.cpu_count() or 0), ""]
    lines += ["| programs | runs | size before inflation | inflated | optimised | optimised / before | "
              "<= before | min IoU | median s | max s |", "|---|---|---|---|---|---|---|---|---|---|"]
    for label, group in (("gt, inflated", [r for r in inflated if r["program"] == "gt"]),
                         ("InverseCSG's, inflated", [r for r in inflated if r["program"] == "inversecsg"]),
                         ("gt, as is", [r for r in as_is if r["program"] == "gt"]),
                         ("InverseCSG's, as is", [r for r in as_is if r["program"] == "inversecsg"])):
        if not group:
            continue
        infl = [r["inflated_size"] for r in group if "inflated_size" in r]
        lines.append("| %s | %d | %.1f | %s | %.1f | %.3f | %.0f %% | %.4f | %.2f | %.2f |" % (
            label, len(group), statistics.mean(r["size"] for r in group),
            "%.1f" % statistics.mean(infl) if infl else "-",
            statistics.mean(r["opt_size"] for r in group), statistics.mean(ratio(r) for r in group),
            100.0 * sum(r["opt_size"] <= r["size"] for r in group) / len(group),
            min(r["opt_iou"] for r in group), statistics.median(r["opt_seconds"] for r in group),
            max(r["opt_seconds"] for r in group)))
    checks = [
        ("every optimised program renders to the same solid (IoU >= 0.999)", bool(ok) and not failed
         and min(r["opt_iou"] for r in ok) >= 0.999),
        ("inflated programs come back to <= 1.05 x their size before inflation on average",
         bool(inflated) and statistics.mean(ratio(r) for r in inflated) <= 1.05),
        (">= 90 % of inflated runs come back to <= their size before inflation",
         bool(inflated) and sum(r["opt_size"] <= r["size"] for r in inflated) >= 0.9 * len(inflated)),
        ("an uninflated program never grows", bool(as_is) and all(r["opt_size"] <= r["size"] for r in as_is)),
        ("median optimisation time <= 2 s", bool(ok) and statistics.median(r["opt_seconds"] for r in ok) <= 2)]
    if args.methods:
        lines += ["", method_table(inflated, args.methods)]
    lines += ["", "Acceptance:", ""] + benchlib.outcome_lines(checks, failed)
    return "\n".join(lines) + "\n", failed


# Seed 001's Table 2: milliseconds of each remaining-solid optimiser on its data set 1 (its own
# models, a quad-core 2.8 GHz CPU); "-" where QMcC could not do model 8.
SEED_TABLE_2 = {"model2": (1572, 1066, 17305, 21526), "model8": (None, 1163, 111017, 79829),
                "model10": (3928, 940, 3347, 22094), "model11": (3879, 900, 8594, 90971)}


def method_table(rows, methods):
    """Each method's median and max wall time (the whole `csgfit optimize`, reading and writing
    included) and mean size ratio on the seed-1 inflations, beside the seed's Table 2."""
    out = ["| method | runs | median s | max s | optimised / before | min IoU |", "|---|---|---|---|---|---|"]
    for m in methods:
        tag = "m_" + m
        done = [r for r in rows if tag + "_iou" in r]
        if not done:
            continue
        out.append("| %s | %d | %.2f | %.2f | %.3f | %.4f |" % (
            m, len(done), statistics.median(r[tag + "_seconds"] for r in done),
            max(r[tag + "_seconds"] for r in done),
            statistics.mean(r[tag + "_size"] / r["size"] for r in done), min(r[tag + "_iou"] for r in done)))
    out += ["", "Seed 001's Table 2 (ms, its models, data set 1): QMcC / Espresso / Set Cover / GA:", ""]
    for model, times in SEED_TABLE_2.items():
        out.append("- %s: %s" % (model, " / ".join("-" if t is None else str(t) for t in times)))
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cli", default=os.path.join(REPO, "build", "bin", "csgfit"))
    ap.add_argument("--data", default=DEFAULT_DATA, help="the inversecsg folder")
    ap.add_argument("--bench-dir", dest="data", help="the same as --data (the smoke tests' name)")
    ap.add_argument("--out", default="/tmp/csgfit_bench_optimize")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--grid", type=int, default=96)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=600)
    ap.add_argument("--programs", default="gt,inversecsg")
    ap.add_argument("--only", nargs="*", help="model names")
    ap.add_argument("--methods", type=lambda v: [m for m in v.split(",") if m], default=[],
                    help="also run these --method values on each seed-1 inflation, e.g. espresso,qmc,setcover,ga")
    ap.add_argument("--extra", nargs=argparse.REMAINDER, default=[], help="more csgfit optimize options")
    ap.add_argument("--write-doc", help="docs/BENCHMARKS.md: rewrite its benchopt section")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    t0 = time.monotonic()
    items = entries(args)

    def progress(rs):
        for r in rs:
            print("%-28s %-10s %-11s %-15s size %s -> %s iou %s %s" % (
                r["name"], r["program"], r["run"], r["status"], r.get("inflated_size", r.get("size")),
                r.get("opt_size", "-"), "%.4f" % r["opt_iou"] if "opt_iou" in r else "-", r.get("error", "")),
                file=sys.stderr, flush=True)
    rows = [r for rs in benchlib.run_all(lambda e: one(e, args), items, args.jobs, progress) for r in rs]
    text, failed = report(rows, args)
    benchlib.write_csv(os.path.join(args.out, "results.csv"), rows,
                       ["name", "program", "run", "status", "size", "primitives", "inflated_size", "opt_size",
                        "opt_primitives", "opt_iou", "opt_seconds", "error"])
    print(text)
    print("%s: %d runs in %.0f s" % (PROG, len(rows), time.monotonic() - t0), file=sys.stderr)
    if args.write_doc:
        benchlib.write_doc(args.write_doc, text, "<!-- benchopt:begin -->", "<!-- benchopt:end -->")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
