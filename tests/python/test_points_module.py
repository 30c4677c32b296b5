"""Tests of the csgfit module's point-cloud fit (csgfit.fit_points: seed 004, what `csgfit points`
runs): arrays and files in, the tree with its NURBS terminal and seed 004's terms out, every output
written, bad clouds and arguments one line (run with /usr/bin/python3 -m pytest tests/python)."""

import json
import os

import numpy as np
import pytest

from built import csgfit  # noqa: E402


def box_points(lo=(0, 0, 0), hi=(20, 12, 8), step=0.5):
    """Points on an axis-aligned box's whole surface and their outward normals."""
    pts, nrm = [], []
    for axis in range(3):
        a, b = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, 1):
            for u in np.arange(lo[a] + step / 2, hi[a], step):
                for v in np.arange(lo[b] + step / 2, hi[b], step):
                    p, n = [0.0] * 3, [0.0] * 3
                    p[axis], p[a], p[b] = (hi if side else lo)[axis], u, v
                    n[axis] = 1.0 if side else -1.0
                    pts.append(p)
                    nrm.append(n)
    return np.array(pts), np.array(nrm)


def dome_points():
    """z = 6 + 2 sin(x / 9) + cos(y / 7) over 40 x 25 mm, sampled from above (no normals)."""
    xs, ys = np.meshgrid(np.linspace(0, 40, 41), np.linspace(0, 25, 26))
    z = 6 + 2 * np.sin(xs / 9) + np.cos(ys / 7)
    return np.column_stack([xs.ravel(), ys.ravel(), z.ravel()])


def leaves(node):
    if isinstance(node, csgfit.Node):
        return [leaf for c in node.children for leaf in leaves(c)]
    return [node]


def test_a_box_scanned_all_around_comes_back_as_a_box(tmp_path):
    points, normals = box_points()
    r = csgfit.fit_points(points, normals, time=6, seed=3)
    assert isinstance(r, csgfit.PointsFitResult)
    assert r.scan == "all" and r.search == "gp" and r.islands == 4 and r.generations > 0
    assert r.fitness.mean_distance < 0.1 and r.patch_rms is None
    boxes = [leaf for leaf in leaves(r.tree) if leaf.type == "box"]
    assert any(sorted(b.size) == pytest.approx([8, 12, 20], abs=0.2) for b in boxes)
    assert r.report().startswith("scan: all, ") and "fitness" in r.report()
    # Every output of `csgfit points -o`, from the one fit.
    for name in ("box.json", "box.scad", "box.step"):
        assert os.path.getsize(r.save(tmp_path / name)) > 0
    assert json.loads((tmp_path / "box.json").read_text())["tree"] == r.document["tree"]
    assert "polyhedron" not in (tmp_path / "box.scad").read_text()


def test_a_height_field_array_gives_a_nurbs_terminal_with_estimated_normals(tmp_path):
    r = csgfit.fit_points(dome_points(), time=5, seed=1)
    assert r.scan == "top"
    patches = [leaf for leaf in leaves(r.tree) if leaf.type == "nurbs"]
    assert patches, r.tree
    assert r.patch_rms < 0.01 and r.fitness.mean_distance < 0.05
    assert "NURBS patch rms" in r.report()
    scad = r.to_scad()
    assert "polyhedron of" in scad and "deviation <=" in scad


def test_a_point_file_and_the_hill_climbing(tmp_path):
    points, normals = box_points(step=1.0)
    path = tmp_path / "box.xyz"
    np.savetxt(path, np.hstack([points, normals]), fmt="%.6f")
    r = csgfit.fit_points(path, time=4, islands=1)
    assert r.islands == 1 and r.sources == [str(path)]
    hill = csgfit.fit_points(str(path), search="hill", time=4)
    assert hill.search == "hill" and hill.islands == 0 and hill.first_tree == "voxels"


def test_cancel_returns_the_tree_so_far():
    points, normals = box_points(step=1.0)
    token = csgfit.CancelToken()
    token.cancel()
    r = csgfit.fit_points(points, normals, time=20, cancel=token)
    assert r.stats.stop_reason == "cancelled" and r.stats.seconds < 10


def one_line_input_error(call, *words):
    with pytest.raises(csgfit.InputError) as e:
        call()
    text = str(e.value)
    assert text and "\n" not in text, text
    for w in words:
        assert w in text, text


def test_bad_clouds_and_arguments_are_one_line(tmp_path):
    points, normals = box_points(step=2.0)
    nan = points.copy()
    nan[5, 2] = np.inf
    one_line_input_error(lambda: csgfit.fit_points(nan, normals), "points", "5", "finite")
    zero = normals.copy()
    zero[3] = 0
    one_line_input_error(lambda: csgfit.fit_points(points, zero), "normal", "zero length")
    one_line_input_error(lambda: csgfit.fit_points(points[:8], normals[:8]), "too few points")
    line = np.column_stack([np.arange(60.0), 2 * np.arange(60.0), np.full(60, 3.0)])
    one_line_input_error(lambda: csgfit.fit_points(line, np.tile([0, 0, 1.0], (60, 1))), "line")
    one_line_input_error(lambda: csgfit.fit_points(points, normals[:9]), "normals", "9")
    one_line_input_error(lambda: csgfit.fit_points(points, search="annealing"), "search")
    one_line_input_error(lambda: csgfit.fit_points(points, scan="sideways"), "scan")
    one_line_input_error(lambda: csgfit.fit_points(points, islands=0), "islands")
    one_line_input_error(lambda: csgfit.fit_points(points, floor=float("nan")), "floor")
    one_line_input_error(lambda: csgfit.fit_points(points, primitives="box,blob"), "blob")
    one_line_input_error(lambda: csgfit.fit_points(points, search="range", islands=2), "range")
    one_line_input_error(lambda: csgfit.fit_points(tmp_path / "part.stl"), "fit_range")
    short = tmp_path / "short.ply"
    short.write_text("ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n")
    one_line_input_error(lambda: csgfit.fit_points(short), "truncated")
