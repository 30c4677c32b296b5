"""What the 2D and 3D benchmark drivers (bench_2d.py, bench_3d.py) do the same way.

Arguments, the manifest, the csgfit run and its summary line, the job pool, the CSV, the
Markdown report's shared lines and the docs/BENCHMARKS.md section. The drivers keep what is
particular to bitmaps or meshes; messages carry the driver's name (`prog`), so that a run
prints what it printed before the two were written once.
"""

import concurrent.futures
import csv
import datetime
import json
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import time

import numpy as np

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(SCRIPT_DIR)
SHARED_BENCH_DIR = os.path.normpath(os.path.join(REPO_DIR, "..", "shared", "benchmarks"))

# ----------------------------------------------------------------------------------------------
# Arguments and inputs


def add_run_args(ap, dim, noun, time_default):
    """--cli, --bench-dir, --time, --jobs and --only, with `noun` ("bitmaps", "models")."""
    ap.add_argument("--cli", default=os.path.join(REPO_DIR, "build", "bin", "csgfit"))
    ap.add_argument("--bench-dir", default=default_bench_dir(dim))
    ap.add_argument("--time", type=float, default=time_default, help="csgfit --time budget (s)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="%s in parallel (default 1: the solver uses every core itself)" % noun)
    ap.add_argument("--only", nargs="+", metavar="NAME", help="run only these %s" % noun)


def add_output_args(ap, dim):
    """--out (bench-out/<dim>) and --extra-args."""
    ap.add_argument("--out", default=os.path.join(REPO_DIR, "bench-out", dim))
    ap.add_argument("--extra-args", default="", help="appended to every csgfit command")


def add_doc_arg(ap, dim):
    """--write-doc [MD]: the bench<dim> section of docs/BENCHMARKS.md by default."""
    ap.add_argument("--write-doc", nargs="?", const=os.path.join(REPO_DIR, "docs",
                                                                 "BENCHMARKS.md"),
                    metavar="MD", help="replace the bench%s section of docs/BENCHMARKS.md" % dim)


def default_bench_dir(dim):
    """../shared/benchmarks/2d, or the InverseCSG set of ../shared/benchmarks/3d."""
    if dim == "3d":
        return os.path.join(SHARED_BENCH_DIR, "3d", "inversecsg")
    return os.path.join(SHARED_BENCH_DIR, dim)


def load_entries(args, prog, list_keys, noun):
    """The manifest's entries, narrowed to --only; (entries, None) or (None, exit status).

    A missing manifest is a skip (status 0, said on stdout); an unknown --only name is bad
    usage (2). `list_keys` are the keys, in order, under which a dict manifest lists them."""
    entries = read_manifest(args.bench_dir, prog, list_keys)
    if entries is None:
        return None, 0
    entries = select_only(entries, args.only, prog, noun)
    return (None, 2) if entries is None else (entries, None)


def read_manifest(bench_dir, prog, list_keys):
    """The entries of bench_dir/manifest.json, or None (said on stdout: skipped) when there is
    none; a driver that runs several sets reads each one's manifest this way."""
    manifest = os.path.join(bench_dir, "manifest.json")
    if not os.path.exists(manifest):
        print("%s: %s not found: skipped" % (prog, manifest))
        return None
    with open(manifest) as f:
        entries = json.load(f)
    if isinstance(entries, dict):
        entries = next((entries[k] for k in list_keys if entries.get(k)), [])
    return entries


def select_only(entries, only, prog, noun):
    """The entries named in `only` (all when it is empty), or None when a name is unknown
    (said on stderr): a typo must not quietly run nothing."""
    if not only:
        return entries
    unknown = set(only) - {e["name"] for e in entries}
    if unknown:
        print("%s: unknown %s(s): %s" % (prog, noun, " ".join(sorted(unknown))),
              file=sys.stderr)
        return None
    return [e for e in entries if e["name"] in set(only)]


def missing_tool(prog, tool):
    """True (and says so on stderr) when `tool` is not on PATH."""
    if shutil.which(tool) is None:
        print("%s: %s not found (apt-get install %s)" % (prog, tool, tool), file=sys.stderr)
        return True
    return False


def missing_cli(prog, cli, hint):
    """True (and says so on stderr) when the csgfit CLI is not an executable file."""
    if os.path.isfile(cli) and os.access(cli, os.X_OK):
        return False
    print("%s: CLI %s not found (build it, or pass %s)" % (prog, cli, hint), file=sys.stderr)
    return True


def remove_files(*paths):
    """Removes those of `paths` that exist."""
    for path in paths:
        if os.path.exists(path):
            os.remove(path)


# ----------------------------------------------------------------------------------------------
# The csgfit run

SUMMARY_RE = re.compile(r"IoU\s*[=:]?\s*(?P<iou>[0-9.]+)")
PRIMS_RE = re.compile(r"(?P<n>\d+)\s+primitives?")
EVALS_RE = re.compile(r"(?P<n>\d+)\s+evaluations?")
SECONDS_RE = re.compile(r"(?P<s>[0-9.]+)\s*s\b")
STOP_RE = re.compile(r"\(([^()]*)\)\s*$")
STATS_KEYS = ("iou", "primitives", "evaluations", "seconds")

# CSV column <- summary key; the 3D driver adds the stop reason.
SOLVER_COLUMNS = {"solver_iou": "iou", "solver_primitives": "primitives",
                  "solver_evaluations": "evaluations", "solver_seconds": "seconds"}


def parse_summary(stderr, json_stats=False):
    """The CLI's final summary line ('csgfit: IoU 0.98, 12 primitives, 340 trees, 34567
    evaluations, 29.93 s (time)'): a dict of the keys found (iou, primitives, evaluations,
    seconds, stop). With `json_stats`, the numbers of a JSON stats line come first."""
    out = {}
    if json_stats:
        out.update(_json_stats(stderr))
    lines = [l for l in stderr.splitlines() if SUMMARY_RE.search(l) and PRIMS_RE.search(l)]
    if lines:
        line = lines[-1].strip()
        out.setdefault("iou", float(SUMMARY_RE.search(line).group("iou")))
        out.setdefault("primitives", int(PRIMS_RE.search(line).group("n")))
        if EVALS_RE.search(line):
            out.setdefault("evaluations", int(EVALS_RE.search(line).group("n")))
        secs = SECONDS_RE.findall(line.split("evaluations")[-1])
        if secs:
            out.setdefault("seconds", float(secs[-1]))
        stop = STOP_RE.search(line)
        if stop:
            out.setdefault("stop", stop.group(1).strip())
    return out


def _json_stats(stderr):
    out = {}
    for line in stderr.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                obj = json.loads(line)
            except ValueError:
                continue
            stats = obj.get("stats", obj) if isinstance(obj, dict) else {}
            for key in STATS_KEYS:
                if key in stats:
                    out[key] = stats[key]
    return out


def solver_cells(summary, columns=SOLVER_COLUMNS):
    """The row's solver columns from a parsed summary ("" where the summary lacks one)."""
    return {col: summary.get(key, "") for col, key in columns.items()}


def csgfit_command(args, command, source, scad, options=()):
    """`csgfit COMMAND SOURCE -o SCAD --time T [options] [--extra-args]` as a list."""
    return ([args.cli, command, source, "-o", scad, "--time", "%g" % args.time] + list(options)
            + shlex.split(args.extra_args))


def command_text(cmd):
    """The command as one shell-quoted line, for the CSV."""
    return " ".join(shlex.quote(c) for c in cmd)


def run_cli(cmd, row, scad, log, timeout, summary_cells, wall_file=None):
    """Runs one timed csgfit command into `row` (command, wall_s, exit_code and the columns
    `summary_cells(stderr)` returns); stderr goes to `log`, the wall time to `wall_file`.

    Returns None when the CLI wrote `scad`, else the error text, with row["status"] set to
    cli-timeout or cli-fail."""
    row["command"] = command_text(cmd)
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        row["wall_s"] = time.monotonic() - t0
        row["exit_code"] = proc.returncode
        with open(log, "w") as f:
            f.write(proc.stderr)
        if wall_file:
            with open(wall_file, "w") as f:
                f.write("%.3f\n" % row["wall_s"])
        if proc.returncode != 0:
            last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
            raise RuntimeError("csgfit exit %d: %s" % (proc.returncode, last[:200]))
        row.update(summary_cells(proc.stderr))
        if not os.path.exists(scad):
            raise RuntimeError("csgfit exited 0 but wrote no .scad")
    except subprocess.TimeoutExpired:
        row["wall_s"] = time.monotonic() - t0
        row["status"] = "cli-timeout"
        return "csgfit did not finish"
    except Exception as exc:
        row["status"] = "cli-fail"
        return str(exc)
    return None


def run_all(fn, items, jobs, progress=None):
    """fn(item) for every item on `jobs` threads; progress(result) as each one ends.
    Returns the results in the order of `items`."""
    results = [None] * len(items)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {pool.submit(fn, item): i for i, item in enumerate(items)}
        for fut in concurrent.futures.as_completed(futures):
            results[futures[fut]] = fut.result()
            if progress:
                progress(results[futures[fut]])
    return results


def print_progress(row, name_width, cells):
    """One stderr line for a finished row: its name and status, then a "LABEL VALUE" per
    (label, key, format, width) of `cells` ("-" when the row has no such key; format None:
    the value as it is), then the row's error."""
    parts = ["%-*s" % (name_width, row["name"]), "%-13s" % row["status"]]
    for label, key, form, width in cells:
        value = row.get(key, "-") if form is None else (form % row[key] if key in row else "-")
        parts.append("%s %-*s" % (label, width, value))
    parts.append("%s" % (row.get("error", ""),))
    print(" ".join(parts), file=sys.stderr, flush=True)


def iou(a, b):
    """Intersection over union of two bool arrays (1 when both are empty)."""
    union = np.count_nonzero(a | b)
    return 1.0 if union == 0 else np.count_nonzero(a & b) / union


# ----------------------------------------------------------------------------------------------
# Tables and the report


def numeric(rows, key):
    """The rows' values of `key` that read as numbers, as floats."""
    out = []
    for r in rows:
        v = r.get(key, "")
        if v not in ("", None):
            try:
                out.append(float(v))
            except ValueError:
                pass
    return out


def cell(row, key, digits=None):
    """A table cell: row[key] with `digits` decimals, or "-" when it is missing."""
    v = row.get(key, "")
    if v in ("", None):
        return "-"
    return ("%.*f" % (digits, float(v))) if digits is not None else str(v)


def fmt(values, fn, digits, na="n/a"):
    """fn(values) with `digits` decimals, `na` when there are none."""
    return na if not values else ("%.*f" % (digits, fn(values)))


def markdown_table(columns, cells):
    """A Markdown table: `columns` [(header, alignment such as "---" or "--:")], `cells` one
    list of strings per row; drivers pick their columns per report instead of writing the
    header and the format string twice."""
    lines = ["| %s |" % " | ".join(h for h, _ in columns),
             "|%s|" % "|".join(a for _, a in columns)]
    lines += ["| %s |" % " | ".join(row) for row in cells]
    return "\n".join(lines)


def kind_order(kinds, labels):
    """The kinds present, those of `labels` first in its order, then the others as met."""
    kinds = list(dict.fromkeys(kinds))
    return [k for k in labels if k in kinds] + [k for k in kinds if k not in labels]


def kind_groups(rows, labels):
    """[(label, rows of that kind)] in kind_order."""
    groups = {}
    for r in rows:
        groups.setdefault(r["kind"], []).append(r)
    return [(labels.get(k, k), groups[k]) for k in kind_order(groups, labels)]


def git_commit():
    """The repository's short HEAD, or "?"."""
    try:
        return subprocess.run(["git", "-C", REPO_DIR, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip() or "?"
    except (OSError, subprocess.SubprocessError):
        return "?"


def now():
    """The report's time stamp."""
    return datetime.datetime.now().strftime("%Y-%m-%d %H:%M")


def measured_line(args, command, count, detail="", note=""):
    """The report's first line: when, which commit, which command, how many of what on how
    many cores; `detail` ends with ", " and stands before the cores, `note` after them."""
    extra = (" " + args.extra_args) if args.extra_args else ""
    return ("Measured %s, commit %s, `csgfit %s --time %g%s`, %s, --jobs %d, %s%d cores (%s).%s\n"
            % (now(), git_commit(), command, args.time, extra, count, args.jobs, detail,
               os.cpu_count() or 0, platform.platform(terse=True), note))


def outcome_lines(checks, failed):
    """The report's acceptance lines (PASS / FAIL / n/a) and, when any row failed, its
    failures; starts with the acceptance list itself (the caller writes its heading)."""
    out = []
    for text, ok in checks:
        mark = "n/a" if ok is None else ("PASS" if ok else "FAIL")
        out.append("- %s: %s" % (mark, text))
    if failed:
        out.append("\nFailures:\n")
        for r in failed:
            out.append("- `%s`: %s (%s)" % (r["name"], r["status"], r.get("error", "")))
    return out


def write_csv(path, rows, fields):
    """rows as CSV with `fields` as columns; floats with 6 significant digits."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow({k: ("%.6g" % v if isinstance(v, float) else v)
                             for k, v in r.items()})


def write_doc(path, text, begin_marker, end_marker):
    """Replaces what stands between the two markers of the Markdown file `path` by `text`."""
    try:
        with open(path) as f:
            doc = f.read()
    except OSError as e:
        raise SystemExit("cannot read %s: %s" % (path, e.strerror))
    begin, end = doc.find(begin_marker), doc.find(end_marker)
    if begin < 0 or end < begin:
        raise SystemExit("%s has no %s ... %s section" % (path, begin_marker, end_marker))
    doc = doc[:begin + len(begin_marker)] + "\n" + text + doc[end:]
    with open(path, "w") as f:
        f.write(doc)


def finish(prog, dim, noun, rows, fields, text, args, t_start, doc_sections=None):
    """Writes --out/results.csv, prints the report and the run's last stderr line, and
    rewrites the doc section (markers <!-- bench<dim>:begin/end -->) when asked.

    `doc_sections` ([(marker, text)], markers <!-- bench<marker>:begin/end -->) replaces that
    one section when a report has several (bench_3d.py: one per benchmark set)."""
    csv_path = os.path.join(args.out, "results.csv")
    write_csv(csv_path, rows, fields)
    print(text)
    print("%s: %d %s in %.0f s; results in %s" % (
        prog, len(rows), noun, time.monotonic() - t_start, csv_path), file=sys.stderr)
    if args.write_doc:
        for marker, section in (doc_sections if doc_sections is not None else [(dim, text)]):
            write_doc(args.write_doc, section, "<!-- bench%s:begin -->" % marker,
                      "<!-- bench%s:end -->" % marker)
        print("%s: updated %s" % (prog, args.write_doc), file=sys.stderr)
