#!/usr/bin/python3
"""Micro-benchmarks: runs csgfit_bench (Google Benchmark) and tabulates incremental vs plain.

Prints Markdown tables: for every 2D and 3D evaluator case, the time of one incremental
try_leaf and update_leaf beside one plain evaluation (render the whole tree, count the
mismatch) and the speed-up, all measured in the same run; then the local optimiser and the
voxeliser. With --repetitions N every benchmark runs N times (interleaved at random, so that a
burst of load on a shared machine does not fall on one side of a ratio) and medians are
reported. --write-doc replaces the section between <!-- micro:begin --> and
<!-- micro:end --> of docs/BENCHMARKS.md.

Build the binary first: cmake -DCSGFIT_BUILD_BENCH=ON, target csgfit_bench (docs/BENCHMARKS.md).
Exit status 1 if the binary fails or any benchmark reports an error (e.g. the two evaluators
disagree on a case).
"""

import argparse
import datetime
import json
import os
import re
import subprocess
import sys

import benchlib

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(SCRIPT_DIR)
DOC_BEGIN = "<!-- micro:begin -->"
DOC_END = "<!-- micro:end -->"

EVAL = re.compile(r"^Eval(2D|3D)_(IncrementalTry|IncrementalUpdate|Plain)/leaves:(\d+)/size:(\d+)$")
LOCAL_OPT = re.compile(r"^LocalOpt(2D|3D)/leaves:(\d+)/size:(\d+)$")
VOXELIZE = re.compile(r"^Voxelize/([^/]+)/resolution:(\d+)(/real_time)?$")

TO_US = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}


def run_bench(args):
    cmd = [args.bench, "--benchmark_format=json"]
    if args.repetitions > 1:
        cmd += ["--benchmark_repetitions=%d" % args.repetitions,
                "--benchmark_report_aggregates_only=true",
                "--benchmark_enable_random_interleaving=true"]
    if args.filter:
        cmd.append("--benchmark_filter=" + args.filter)
    if args.min_time is not None:
        cmd.append("--benchmark_min_time=%g" % args.min_time)
    print("running: " + " ".join(cmd), file=sys.stderr)
    # The binary's progress and warnings go to stderr, which is passed through.
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, text=True)
    try:
        data = json.loads(proc.stdout)
    except ValueError:
        raise SystemExit("%s exited with %d and no JSON report" % (args.bench, proc.returncode))
    if proc.returncode != 0:
        print("warning: %s exited with %d" % (args.bench, proc.returncode), file=sys.stderr)
    return data, proc.returncode


def results(data):
    """run name -> entry: the median aggregate when there are repetitions, else the one run;
    and the list of (name, message) of benchmarks that reported an error."""
    runs, errors = {}, []
    for b in data.get("benchmarks", []):
        name = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            errors.append((name, b.get("error_message", "")))
            continue
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") == "median":
                runs[name] = b
        elif name not in runs:
            runs[name] = b
    return runs, sorted(set(errors))


def micros(entry, real=False):
    return entry["real_time" if real else "cpu_time"] * TO_US[entry.get("time_unit", "ns")]


def fmt_time(us):
    if us >= 1e4:
        return "%.0f" % us
    if us >= 100:
        return "%.1f" % us
    return "%.2f" % us


def eval_table(runs, dim):
    cases = {}
    for name, entry in runs.items():
        m = EVAL.match(name)
        if m and m.group(1) == dim:
            cases.setdefault((int(m.group(3)), int(m.group(4))), {})[m.group(2)] = entry
    if not cases:
        return None
    power = "^2" if dim == "2D" else "^3"
    unit = "pixels" if dim == "2D" else "voxels"
    lines = ["| leaves | %s | depth | try_leaf µs | update_leaf µs | plain µs | "
             "speed-up try | speed-up update |" % unit,
             "|--:|--:|--:|--:|--:|--:|--:|--:|"]
    for (leaves, size) in sorted(cases, key=lambda k: (k[1], k[0])):
        c = cases[(leaves, size)]
        plain = c.get("Plain")
        row = ["%d" % leaves, "%d%s" % (size, power)]
        any_entry = next(iter(c.values()))
        row.append("%d" % any_entry["depth"] if "depth" in any_entry else "")
        for key in ("IncrementalTry", "IncrementalUpdate", "Plain"):
            row.append(fmt_time(micros(c[key])) if key in c else "-")
        for key in ("IncrementalTry", "IncrementalUpdate"):
            if plain and key in c and micros(c[key]) > 0:
                row.append("**%.1f x**" % (micros(plain) / micros(c[key])))
            else:
                row.append("-")
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def local_opt_table(runs):
    rows = []
    for name, entry in runs.items():
        m = LOCAL_OPT.match(name)
        if m:
            rows.append((m.group(1), int(m.group(3)), int(m.group(2)), entry))
    if not rows:
        return None
    lines = ["| | leaves | grid | ms | evaluations | µs per evaluation | accepted moves | "
             "mismatch before -> after |",
             "|---|--:|--:|--:|--:|--:|--:|--:|"]
    for dim, size, leaves, e in sorted(rows):
        us = micros(e)
        evals = e.get("evaluations", 0)
        lines.append("| %s | %d | %d%s | %s | %d | %s | %d | %d -> %d |" % (
            dim, leaves, size, "^2" if dim == "2D" else "^3", fmt_time(us / 1e3), evals,
            fmt_time(us / evals) if evals else "-", e.get("accepted", 0),
            e.get("mismatch_before", 0), e.get("mismatch_after", 0)))
    return "\n".join(lines)


def voxelize_table(runs):
    rows = []
    for name, entry in runs.items():
        m = VOXELIZE.match(name)
        if m:
            rows.append((m.group(1), int(m.group(2)), entry))
    if not rows:
        return None
    lines = ["| mesh | resolution | triangles | solid voxels | ms (wall) |",
             "|---|--:|--:|--:|--:|"]
    for model, res, e in sorted(rows):
        lines.append("| %s | %d | %d | %d | %s |" % (
            model, res, e.get("triangles", 0), e.get("voxels", 0),
            fmt_time(micros(e, real=True) / 1e3)))
    return "\n".join(lines)


def git_commit():
    try:
        commit = subprocess.run(["git", "-C", REPO_DIR, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", REPO_DIR, "status", "--porcelain",
                                "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "?"
    return (commit or "?") + (" (with uncommitted changes)" if dirty else "")


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def report(data, runs, errors, args):
    ctx = data.get("context", {})
    when = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    load = ctx.get("load_avg") or []
    out = ["Measured %s, commit %s, %s CPUs (%s, %s MHz), load average %s at the start; %s; "
           "CPU time per evaluation (wall time for the voxeliser, which uses two threads)."
           % (when, git_commit(), ctx.get("num_cpus", os.cpu_count() or "?"), cpu_model(),
              ctx.get("mhz_per_cpu", "?"), "%.1f" % load[0] if load else "?",
              "median of %d interleaved repetitions" % args.repetitions
              if args.repetitions > 1 else "one run"), ""]
    for title, table in (("2D evaluator", eval_table(runs, "2D")),
                         ("3D evaluator", eval_table(runs, "3D")),
                         ("Local optimiser (optimize_leaves)", local_opt_table(runs)),
                         ("Voxeliser", voxelize_table(runs))):
        if table:
            out += ["**%s**" % title, "", table, ""]
    if errors:
        out += ["Errors:", ""] + ["- `%s`: %s" % e for e in errors] + [""]
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bench", default=os.path.join(REPO_DIR, "build", "bin", "csgfit_bench"),
                    help="the csgfit_bench binary (default: build/bin/csgfit_bench)")
    ap.add_argument("--repetitions", type=int, default=1,
                    help="runs of every benchmark; > 1 reports medians")
    ap.add_argument("--filter", default="", help="--benchmark_filter regex (e.g. Eval2D)")
    ap.add_argument("--min-time", type=float, default=None,
                    help="--benchmark_min_time in seconds (Google Benchmark's default: 0.5)")
    ap.add_argument("--json-out", help="also save the binary's JSON report here")
    ap.add_argument("--write-doc", nargs="?", const=os.path.join(REPO_DIR, "docs", "BENCHMARKS.md"),
                    help="replace the micro-benchmark section of docs/BENCHMARKS.md "
                         "(or of the given file)")
    args = ap.parse_args(argv)
    if not os.path.isfile(args.bench):
        raise SystemExit("%s not found: build it with -DCSGFIT_BUILD_BENCH=ON --target "
                         "csgfit_bench" % args.bench)
    data, status = run_bench(args)
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump(data, f, indent=1)
    runs, errors = results(data)
    text = report(data, runs, errors, args)
    print(text)
    if errors or status != 0:
        if args.write_doc:
            print("not writing %s: the run had errors" % args.write_doc, file=sys.stderr)
        return 1
    if args.write_doc:
        benchlib.write_doc(args.write_doc, text, DOC_BEGIN, DOC_END)
        print("wrote %s" % args.write_doc, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
