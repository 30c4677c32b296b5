"""Tests of `csgfit points` (seed 004) from the command line: a cloud sampled from a known part
comes back as a solid of the right volume in every output, a NURBS patch is recovered from its
own samples, and every bad cloud is one line, exit 2 and no output file (run with
/usr/bin/python3 -m pytest tests/python)."""

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("CSGFIT_BUILD_DIR", os.path.join(REPO, "build"))
CLI = os.path.join(BUILD, "bin", "csgfit")
pytestmark = pytest.mark.skipif(not os.path.exists(CLI), reason=f"needs {CLI}")


def run(*args):
    return subprocess.run([CLI, "points", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def box_cloud(path, lo=(0, 0, 0), hi=(20, 12, 8), step=0.5, bottom=True):
    """Points on an axis-aligned box's surface with outward normals, as `x y z nx ny nz`."""
    rows = []
    for axis in range(3):
        for side in (0, 1):
            if axis == 2 and side == 0 and not bottom:
                continue
            a, b = (axis + 1) % 3, (axis + 2) % 3
            for u in np.arange(lo[a] + step / 2, hi[a], step):
                for v in np.arange(lo[b] + step / 2, hi[b], step):
                    p, n = [0.0] * 3, [0.0] * 3
                    p[axis], p[a], p[b] = (hi if side else lo)[axis], u, v
                    n[axis] = 1.0 if side else -1.0
                    rows.append(p + n)
    np.savetxt(path, np.array(rows), fmt="%.6f")
    return path


def leaves(node):
    if "op" in node:
        return [leaf for c in node["children"] for leaf in leaves(c)]
    return [node]


def test_a_box_scanned_all_around_comes_back_as_a_box(tmp_path):
    cloud = box_cloud(tmp_path / "box.xyz")
    out = tmp_path / "box.json"
    scad = tmp_path / "box.scad"
    r = run(cloud, "-o", out, "-o", scad, "--time", 6, "--seed", 3, "--report")
    assert r.returncode == 0, r.stderr
    assert "scan: all" in r.stdout and "fitness" in r.stdout
    doc = json.loads(out.read_text())
    assert doc["points"]["scan"] == "all" and doc["points"]["search"] == "gp"
    assert doc["points"]["mean_distance"] < 0.1
    assert "polyhedron" not in scad.read_text()
    # The seed-002 detector's box starts half the islands: the result keeps it.
    boxes = [leaf for leaf in leaves(doc["tree"]) if leaf["type"] == "box"]
    assert any(sorted(b["size"]) == pytest.approx([8, 12, 20], abs=0.2) for b in boxes)


def test_a_height_field_scanned_from_above_gives_a_nurbs_terminal(tmp_path):
    # z = 6 + 2 sin(x / 9) + cos(y / 7) over 40 x 25 mm, seen from above.
    xs, ys = np.meshgrid(np.linspace(0, 40, 41), np.linspace(0, 25, 26))
    z = 6 + 2 * np.sin(xs / 9) + np.cos(ys / 7)
    gx, gy = 2 / 9 * np.cos(xs / 9), -1 / 7 * np.sin(ys / 7)
    n = np.stack([-gx, -gy, np.ones_like(z)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    pts = np.column_stack([xs.ravel(), ys.ravel(), z.ravel(), n.reshape(-1, 3)])
    cloud = tmp_path / "dome.xyz"
    np.savetxt(cloud, pts, fmt="%.6f")
    out = tmp_path / "dome.json"
    r = run(cloud, "-o", out, "--time", 5)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["points"]["scan"] == "top"
    patches = [leaf for leaf in leaves(doc["tree"]) if leaf["type"] == "nurbs"]
    assert patches, doc["tree"]
    assert doc["points"]["patch_rms"] < 0.01
    assert doc["points"]["mean_distance"] < 0.05


@pytest.mark.skipif(shutil.which("openscad") is None, reason="needs openscad")
def test_the_nurbs_scad_renders_and_states_its_deviation(tmp_path):
    xs, ys = np.meshgrid(np.linspace(0, 30, 31), np.linspace(0, 20, 21))
    z = 5 + 0.1 * xs
    pts = np.column_stack([xs.ravel(), ys.ravel(), z.ravel(),
                           np.tile([-0.1, 0, 1] / np.linalg.norm([-0.1, 0, 1]), (xs.size, 1))])
    cloud = tmp_path / "ramp.xyz"
    np.savetxt(cloud, pts, fmt="%.6f")
    scad = tmp_path / "ramp.scad"
    r = run(cloud, "-o", scad, "--time", 3, "--primitives", "nurbs")
    assert r.returncode == 0, r.stderr
    text = scad.read_text()
    assert "polyhedron of" in text and "deviation <=" in text
    stl = tmp_path / "ramp.stl"
    render = subprocess.run(["openscad", "-o", str(stl), str(scad)], capture_output=True,
                            text=True, timeout=300)
    assert render.returncode == 0 and stl.stat().st_size > 0, render.stderr[-500:]


BAD = {
    "nan.xyz": ("0 0 0 0 0 1\nnan 1 1 0 0 1\n" * 15, "NaN or infinite"),
    "zero_normal.xyz": ("".join(f"{i} {i % 3} {i % 5} 0 0 0\n" for i in range(30)), "zero length"),
    "few.xyz": ("".join(f"{i} {i % 3} {i % 5} 0 0 1\n" for i in range(8)), "too few points"),
    "line.xyz": ("".join(f"{i} {2 * i} 3\n" for i in range(60)), "on a line"),
    "short.ply": ("ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\n0 0 0\n1 0 0\n", "truncated"),
    "image.png": ("not an image", "reads .xyz or .ply"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_clouds_are_one_line_and_write_nothing(tmp_path, name):
    text, needle = BAD[name]
    cloud = tmp_path / name
    cloud.write_text(text)
    out = tmp_path / "out.scad"
    r = run(cloud, "-o", out, "--time", 2)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], r.stderr
    assert not out.exists()


def test_a_flat_cloud_all_around_and_bad_options_are_refused(tmp_path):
    flat = tmp_path / "flat.xyz"
    flat.write_text("".join(f"{i % 7} {i // 7} 3 0 0 1\n" for i in range(49)))
    r = run(flat, "-o", tmp_path / "o.scad", "--scan", "all", "--time", 2)
    assert r.returncode == 2 and "on a plane" in r.stderr
    cloud = box_cloud(tmp_path / "box.xyz", step=2)
    for bad in (["--islands", "0"], ["--scan", "sideways"], ["--search", "annealing"],
                ["--floor", "nan"], ["--primitives", "blob"]):
        r = run(cloud, "-o", tmp_path / "o.scad", *bad)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (bad, r.stderr)
    assert not (tmp_path / "o.scad").exists()
