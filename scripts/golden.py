#!/usr/bin/env python3
"""Fixed-seed runs whose output must not change unless a commit says why.

Every run ends by convergence (a large --time), so the same binary gives the same tree on
every machine of the same kind; the JSON the CLI writes and the .scad that `csgfit export`
makes of it are recorded in tests/golden/expected/ and compared number by number (relative
tolerance 1e-9; wall times are ignored).

    golden.py check  [--cli build/bin/csgfit] [--jobs 2] [--only ID ...]
    golden.py record [--cli build/bin/csgfit] [--jobs 2] [--only ID ...]

Exit status: 0 when every output matches (or was recorded), 1 on a difference, 2 on bad usage
or when an input is missing.
"""

import argparse
import concurrent.futures
import json
import math
import os
import re
import struct
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(os.path.dirname(REPO), "shared", "benchmarks")
EXPECTED = os.path.join(REPO, "tests", "golden", "expected")
TOLERANCE = 1e-9
IGNORED_KEYS = {"seconds"}

B2 = os.path.join(SHARED, "2d")
B3 = os.path.join(SHARED, "3d", "inversecsg")

# (id, command, input, extra arguments). Inputs: a path, or "gen:NAME" for one this script
# writes (a voxel array, the test fixture's STL, a turned box). Not OpenSCAD renderings of the
# synthetic models: OpenSCAD triangulates the same file differently from one run to the next.
RUNS = [
    ("2d_glyph_P_fast", "image", f"{B2}/glyph_P.png", "--quality fast --threads 1"),
    ("2d_part_05_fast", "image", f"{B2}/part_05.png", "--quality fast --threads 1"),
    ("2d_cad_0000_fast", "image", f"{B2}/cad_0000.png", "--quality fast --threads 1"),
    ("2d_topopt_mbb_fast", "image", f"{B2}/topopt_mbb_beam.png", "--quality fast --threads 1"),
    ("2d_glyph_R_paper", "image", f"{B2}/glyph_R.png", "--preset paper --threads 1"),
    ("2d_glyph_P_default_2t", "image", f"{B2}/glyph_P.png", "--threads 2 --seed 3"),
    ("2d_eye_fast_2t", "image", f"{B2}/eye_in_diamond.png", "--quality fast --threads 2 --seed 2"),
    ("2d_printer_rect_circle", "image", f"{B2}/icon_printer.png",
     "--quality fast --threads 1 --primitives rectangle,circle"),
    ("2d_part_00_alternatives", "image", f"{B2}/part_00.png",
     "--quality fast --threads 1 --alternatives 2"),
    ("2d_cad_0007_k10", "image", f"{B2}/cad_0007.png", "--quality fast --threads 1 --k 10"),
    ("2d_b_triangles", "image", f"{B2}/glyph_b_lower.png",
     "--quality fast --threads 1 --primitives triangle,rectangle"),
    ("2d_bracket_extruded", "image", f"{REPO}/examples/bracket.png",
     "--quality fast --threads 1 --pixel-size 0.5 --thickness 3"),
    ("3d_011_r32", "mesh", f"{B3}/011/csg_high_res.off", "--resolution 32 --threads 1"),
    ("3d_039_r24", "mesh", f"{B3}/039/csg_high_res.off", "--resolution 24 --threads 1"),
    ("3d_101_r32", "mesh", f"{B3}/101/csg_high_res.off", "--resolution 32 --threads 1"),
    ("3d_011_auto_2t", "mesh", f"{B3}/011/csg_high_res.off", "--threads 2"),
    ("3d_041_r28_all", "mesh", f"{B3}/041/csg_high_res.off",
     "--resolution 28 --threads 1 --primitives all"),
    ("3d_060_r28_all", "mesh", f"{B3}/060/csg_high_res.off",
     "--resolution 28 --threads 1 --primitives all"),
    ("3d_081_r28_2t", "mesh", f"{B3}/081/csg_high_res.off", "--resolution 28 --threads 2"),
    ("3d_rotated_box_auto", "mesh", "gen:rotated_box", "--threads 1"),
    ("3d_holed_block_no_align", "mesh", "gen:holed_block", "--threads 1 --no-align"),
    ("3d_voxels_npy", "mesh", "gen:voxels", "--threads 1 --seed 4"),
]


def generated_input(name, work):
    """Writes the input a `gen:` run needs into `work` and returns its path."""
    if name == "voxels":
        return write_voxel_npy(os.path.join(work, "plate_with_bore.npy"))
    if name == "holed_block":
        path = os.path.join(work, "holed_block.stl")
        subprocess.run([sys.executable, os.path.join(REPO, "tests", "fixtures", "holed_block_stl.py"),
                        path], check=True)
        return path
    if name == "rotated_box":
        return write_rotated_box_stl(os.path.join(work, "rotated_box.stl"))
    raise ValueError(name)


def write_rotated_box_stl(path):
    """A 20 x 10 x 6 box turned by 30 degrees about z and 10 about x: the aligned-frame path."""
    import itertools

    cz, sz = math.cos(math.radians(30)), math.sin(math.radians(30))
    cx, sx = math.cos(math.radians(10)), math.sin(math.radians(10))

    def place(p):
        x, y, z = p[0] * 10, p[1] * 5, p[2] * 3
        y, z = cx * y - sx * z, sx * y + cx * z
        return (cz * x - sz * y, sz * x + cz * y, z)

    corners = {c: place(c) for c in itertools.product((-1, 1), repeat=3)}
    lines = ["solid rotated_box"]
    for axis, sign in itertools.product(range(3), (-1, 1)):
        others = [a for a in range(3) if a != axis]
        quad = []
        for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            c = [0, 0, 0]
            c[axis], c[others[0]], c[others[1]] = sign, u, v
            quad.append(corners[tuple(c)])
        # Counter-clockwise seen from outside (checked: csgfit reports no inward faces).
        if (sign > 0) == (axis == 1):
            quad.reverse()
        for tri in ((quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])):
            lines.append("facet normal 0 0 0\n outer loop")
            lines += [" vertex %.12g %.12g %.12g" % v for v in tri]
            lines.append(" endloop\nendfacet")
    lines.append("endsolid rotated_box")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def write_voxel_npy(path):
    """A 30 x 20 x 8 plate with a bore of radius 5 and a boss, as a uint8 .npy (no numpy)."""
    nx, ny, nz = 34, 24, 16
    cells = bytearray(nx * ny * nz)
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                x, y, z = i + 0.5, j + 0.5, k + 0.5
                plate = 2 <= x <= 32 and 2 <= y <= 22 and 2 <= z <= 10
                bore = (x - 12) ** 2 + (y - 12) ** 2 <= 25
                boss = (x - 25) ** 2 + (y - 12) ** 2 <= 16 and 10 <= z <= 14
                cells[(i * ny + j) * nz + k] = 1 if (plate and not bore) or boss else 0
    header = "{'descr': '|u1', 'fortran_order': False, 'shape': (%d, %d, %d), }" % (nx, ny, nz)
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        f.write(bytes(cells))
    return path


def run_one(cli, run, work):
    """Runs one fit to JSON and exports it to .scad; returns (json_text, scad_text)."""
    rid, command, source, extra = run
    if source.startswith("gen:"):
        source = generated_input(source[4:], work)
    if not os.path.exists(source):
        raise FileNotFoundError(source)
    out_json = os.path.join(work, rid + ".json")
    out_scad = os.path.join(work, rid + ".scad")
    args = [cli, command, source, "-o", out_json, "--time", "900", "--quiet"] + extra.split()
    subprocess.run(args, check=True, capture_output=True, text=True)
    subprocess.run([cli, "export", out_json, "-o", out_scad], check=True, capture_output=True,
                   text=True)
    with open(out_json) as fj, open(out_scad) as fs:
        return fj.read(), fs.read()


def stop_reason(doc):
    return (doc.get("stats") or {}).get("stop_reason")


def differences(expected, actual, where="$"):
    """Paths where two JSON values differ beyond the tolerance."""
    if isinstance(expected, dict) and isinstance(actual, dict):
        out = []
        for key in sorted(set(expected) | set(actual)):
            if key in IGNORED_KEYS:
                continue
            if key not in expected or key not in actual:
                out.append(f"{where}.{key}: only in {'actual' if key in actual else 'expected'}")
                continue
            out += differences(expected[key], actual[key], f"{where}.{key}")
        return out
    if isinstance(expected, list) and isinstance(actual, list):
        if len(expected) != len(actual):
            return [f"{where}: {len(expected)} items expected, {len(actual)} found"]
        out = []
        for i, (e, a) in enumerate(zip(expected, actual)):
            out += differences(e, a, f"{where}[{i}]")
        return out
    if isinstance(expected, (int, float)) and isinstance(actual, (int, float)) \
            and not isinstance(expected, bool) and not isinstance(actual, bool):
        if close(expected, actual):
            return []
        return [f"{where}: {expected!r} expected, {actual!r} found"]
    return [] if expected == actual else [f"{where}: {expected!r} expected, {actual!r} found"]


def close(a, b):
    if a == b:
        return True
    if not (math.isfinite(a) and math.isfinite(b)):
        return False
    return abs(a - b) <= TOLERANCE * max(1.0, abs(a), abs(b))


NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def scad_differences(expected, actual):
    """Lines of two .scad texts that differ beyond the numeric tolerance."""
    e_lines, a_lines = expected.splitlines(), actual.splitlines()
    if len(e_lines) != len(a_lines):
        return [f".scad: {len(e_lines)} lines expected, {len(a_lines)} found"]
    out = []
    for n, (e, a) in enumerate(zip(e_lines, a_lines), 1):
        if e == a:
            continue
        if NUMBER.sub("#", e) == NUMBER.sub("#", a) and all(
                close(float(x), float(y)) for x, y in zip(NUMBER.findall(e), NUMBER.findall(a))):
            continue
        out.append(f".scad line {n}: {e!r} expected, {a!r} found")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mode", choices=["check", "record"])
    parser.add_argument("--cli", default=os.path.join(REPO, "build", "bin", "csgfit"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", nargs="*", default=None)
    args = parser.parse_args()
    runs = [r for r in RUNS if not args.only or r[0] in args.only]
    if args.only and len(runs) != len(args.only):
        print("golden: unknown run id in --only", file=sys.stderr)
        return 2
    if not os.path.isdir(SHARED):
        print(f"golden: {SHARED} is missing", file=sys.stderr)
        return 2
    os.makedirs(EXPECTED, exist_ok=True)
    failed = 0
    with tempfile.TemporaryDirectory() as work, \
            concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = {pool.submit(run_one, args.cli, r, work): r for r in runs}
        for future in concurrent.futures.as_completed(futures):
            rid = futures[future][0]
            try:
                json_text, scad_text = future.result()
            except (subprocess.CalledProcessError, FileNotFoundError) as e:
                detail = getattr(e, "stderr", "") or str(e)
                print(f"golden: {rid}: the run failed: {detail.strip()}")
                failed += 1
                continue
            doc = json.loads(json_text)
            if stop_reason(doc) == "time":
                print(f"golden: {rid}: stopped by the clock, not by convergence")
                failed += 1
                continue
            json_path = os.path.join(EXPECTED, rid + ".json")
            scad_path = os.path.join(EXPECTED, rid + ".scad")
            if args.mode == "record":
                with open(json_path, "w") as f:
                    f.write(json_text)
                with open(scad_path, "w") as f:
                    f.write(scad_text)
                print(f"golden: {rid}: recorded")
                continue
            if not os.path.exists(json_path):
                print(f"golden: {rid}: nothing recorded (run golden.py record)")
                failed += 1
                continue
            with open(json_path) as fj, open(scad_path) as fs:
                diffs = differences(json.load(fj), doc) + scad_differences(fs.read(), scad_text)
            if diffs:
                failed += 1
                print(f"golden: {rid}: {len(diffs)} difference(s), first: {diffs[0]}")
            else:
                print(f"golden: {rid}: same")
    if args.mode == "check":
        print(f"golden: {len(runs) - failed} of {len(runs)} runs give the recorded output")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
