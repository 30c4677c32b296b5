"""Tests of the point-cloud judge, scripts/points_judge.py (/usr/bin/python3 -m pytest tests/python).

The judge must be right before it may call a solver wrong: its B-splines against hand-computed
values, the ground truth as the result at deviation 0 and a raised copy at its 0.05 mm, a
rotated leaf read in the model's frame. No csgfit binary is needed; the tests that render or
open a STEP need OpenSCAD / FreeCAD and ../shared/benchmarks/points and are skipped without.
"""

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(os.path.dirname(REPO), "shared", "benchmarks", "points")
sys.path.insert(0, os.path.join(REPO, "scripts"))
import points_judge as pj  # noqa: E402
import range_judge as rj  # noqa: E402
import stand_in  # noqa: E402  (tests/python/stand_in.py)

needs_data = pytest.mark.skipif(not os.path.isdir(BENCH), reason="needs %s" % BENCH)
needs_openscad = pytest.mark.skipif(
    shutil.which("openscad") is None or not os.path.isdir(BENCH),
    reason="needs openscad and %s" % BENCH)
needs_freecad = pytest.mark.skipif(shutil.which("freecadcmd") is None,
                                   reason="needs freecadcmd")

SAMPLES = (60, 20)  # enough for the checks, a tenth of the benchmark's samples
CLAMPED = [0, 0, 0, 0, 0.2, 0.5, 0.5, 0.9, 1, 1, 1, 1]  # cubic, a double interior knot


def blade_gt():
    with open(os.path.join(BENCH, "blade.gt.json")) as f:
        return json.load(f)


def test_basis_is_a_partition_of_unity():
    t = np.linspace(0, 1, 501)
    for knots, degree in ((CLAMPED, 3), ([0, 0, 0, 0.3, 0.7, 1, 1, 1], 2),
                          ([0, 0, 0, 0, 1, 1, 1, 1], 3)):
        n = pj.basis(knots, degree, t)
        assert n.shape == (501, len(knots) - degree - 1)
        assert np.allclose(n.sum(axis=1), 1.0, atol=1e-12)
        assert n.min() >= -1e-15


def test_basis_against_hand_computed_values():
    # Bezier (Bernstein) at 1/2: (1, 3, 3, 1) / 8; the uniform cubic B-spline at a knot:
    # (1, 4, 1) / 6 on its three live functions; a quadratic with knots 0 0 0 .5 1 1 1 at 1/4:
    # N0 = (1 - 2t)^2 = 1/4, N2 = 2t^2 (the part of t / .5 * t / 1) = 1/8, N1 = the rest, 5/8.
    assert np.allclose(pj.basis([0, 0, 0, 0, 1, 1, 1, 1], 3, [0.5]), np.array([[1, 3, 3, 1]]) / 8)
    assert np.allclose(pj.basis([0, 1, 2, 3, 4, 5, 6, 7], 3, [3.0]), [[1 / 6, 4 / 6, 1 / 6, 0]])
    assert np.allclose(pj.basis([0, 0, 0, 0.5, 1, 1, 1], 2, [0.25]), [[0.25, 0.625, 0.125, 0]])


def test_clamped_basis_interpolates_its_ends():
    n = pj.basis(CLAMPED, 3, [0.0, 1.0])
    assert np.array_equal(n[0], np.eye(8)[0]) and np.array_equal(n[1], np.eye(8)[-1])


def test_basis_derivative_matches_finite_differences():
    t = np.linspace(0.01, 0.99, 97)
    h = 1e-6
    fd = (pj.basis(CLAMPED, 3, t + h) - pj.basis(CLAMPED, 3, t - h)) / (2 * h)
    away = np.min(np.abs(t[:, None] - np.array([0.2, 0.5, 0.9])), axis=1) > 2 * h  # kinks
    assert np.allclose(pj.basis_derivative(CLAMPED, 3, t)[away], fd[away], atol=1e-5)


@needs_data
def test_blade_patch_ends_at_its_corner_control_points():
    gt = pj.patch_from_gt(blade_gt())
    corners = gt.model(np.array([0.0, 1.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0, 1.0]))
    assert np.allclose(corners, gt.net[[0, -1, 0, -1], [0, 0, -1, -1]], atol=1e-12)


@needs_data
@pytest.mark.parametrize("how, mean, most", [("exact", 0.0, 0.0), ("shifted", 0.05, 0.05)])
def test_blade_deviation_of_the_ground_truth_and_of_a_raised_copy(how, mean, most):
    gt = pj.patch_from_gt(blade_gt())
    leaf = json.loads(json.dumps(pj.gt_as_leaf(blade_gt(), how)))  # as a file would hold it
    assert leaf["counts"] == [15, 4] and leaf["center"] == [30.0, 10.0, 0.0]
    dev = pj.deviation(gt, [pj.patch_from_leaf(leaf)], SAMPLES)
    assert dev["dev_mean"] == pytest.approx(mean, abs=1e-9)
    assert dev["dev_max"] == pytest.approx(most, abs=1e-9)
    assert dev["outside"] == 0


@needs_data
def test_scaled_heights_are_caught_and_a_patch_beside_the_blade_is_outside():
    gt = pj.patch_from_gt(blade_gt())
    scaled = pj.deviation(gt, [pj.patch_from_leaf(pj.gt_as_leaf(blade_gt(), "scaled"))], SAMPLES)
    assert 0.08 < scaled["dev_mean"] < 0.12 and scaled["dev_max"] < 0.16  # 1 % of 5 .. 15 mm
    moved = pj.gt_as_leaf(blade_gt(), "exact")
    moved["center"][0] += 6.0  # a tenth of the blade off its rectangle
    far = pj.deviation(gt, [pj.patch_from_leaf(moved)], SAMPLES)
    # the samples beside it count at their distance to its edge: up to 6 mm less half a cell
    assert far["outside"] == SAMPLES[0] // 10 * SAMPLES[1] and far["dev_max"] > 5.0


def flat_leaf(height, quaternion, center):
    """A bicubic 4 x 3 patch over 10 x 6 mm at a constant `height`, control points at the
    Greville abscissae: its top is the plane z = height in local coordinates."""
    knots_u, knots_v = [0, 0, 0, 0, 1, 1, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1]
    gu, gv = np.array([0, 1, 2, 3]) / 3.0, np.array([0, 1, 2, 3]) / 3.0
    net = np.zeros((4, 4, 3))
    net[..., 0], net[..., 1] = -5 + 10 * gu[:, None], -3 + 6 * gv[None, :]
    net[..., 2] = height
    patch = pj.Patch((3, 3), knots_u, knots_v, net, center)
    return pj.leaf_from_patch(patch, quaternion)


def test_rotated_leaf_is_read_in_the_model_frame():
    half = np.radians(30) / 2  # 30 degrees about y
    q = (np.cos(half), 0.0, np.sin(half), 0.0)
    center = [4.0, -2.0, 1.0]
    leaf = flat_leaf(2.0, q, center)
    patch = pj.patch_from_leaf(leaf)
    rot = rotation_y(30)
    assert np.allclose(patch.rotation, rot)
    assert np.allclose(patch.model(np.array([0.0]), np.array([0.0]))[0],
                       center + rot @ np.array([-5, -3, 2.0]))
    # The top is the plane through c + R (0, 0, 2) with normal R e_z: a vertical line at
    # (x, y) meets it where that plane's equation says.
    x, y = np.array([3.0, 4.0, 5.5]), np.array([-2.0, -3.5, 0.0])
    z, hit, _ = pj.heights(patch, x, y)
    p0, nrm = center + rot @ [0, 0, 2.0], rot @ [0, 0, 1.0]
    want = p0[2] - (nrm[0] * (x - p0[0]) + nrm[1] * (y - p0[1])) / nrm[2]
    assert hit.all() and np.allclose(z, want, atol=1e-9)
    # euler_deg (OpenSCAD's rotate) is read when the quaternion is missing
    del leaf["rotation"]
    leaf["euler_deg"] = [0, 30, 0]
    assert np.allclose(pj.patch_from_leaf(leaf).rotation, rot)


def rotation_y(deg):
    a = np.radians(deg)
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def test_leaf_control_points_are_u_fastest():
    leaf = flat_leaf(1.0, (1.0, 0.0, 0.0, 0.0), [0, 0, 0])
    leaf["control_points"] = [[0, 0, k] for k in range(16)]
    net = pj.patch_from_leaf(leaf).net
    assert net[1, 0, 2] == 1 and net[0, 1, 2] == 4 and net[3, 2, 2] == 3 + 4 * 2
    assert pj.leaf_from_patch(pj.patch_from_leaf(leaf))["control_points"] == [
        [0.0, 0.0, float(k)] for k in range(16)]
    doc = {"tree": {"op": "intersection", "children": [{"type": "box"}, leaf]}}
    assert pj.nurbs_leaves(doc) == [leaf]


def test_polyhedron_is_closed_and_outward():
    tris = np.array(pj._polyhedron_faces(3, 2))
    edges = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    assert all(n == 1 and edges.get((b, a)) == 1 for (a, b), n in edges.items())
    patch = pj.patch_from_leaf(flat_leaf(2.0, (1.0, 0.0, 0.0, 0.0), [0, 0, 0]))
    top = patch.grid(4, 3).transpose(1, 0, 2).reshape(-1, 3)
    pts = np.concatenate([top, top * [1, 1, 0]])[tris]
    volume = np.einsum("ij,ij->i", pts[:, 0], np.cross(pts[:, 1], pts[:, 2])).sum() / 6
    assert volume == pytest.approx(10 * 6 * 2)


def test_header_deviation_is_read():
    text = ("// csgfit\n// nurbs_1: polyhedron of 120x40 cells, deviation <= 0.0012 mm from the "
            "exact B-spline patch\n// nurbs_2: polyhedron of 8x8 cells, deviation <= 3e-05 mm "
            "from the exact B-spline patch\n")
    assert pj.header_deviations(text) == {"nurbs_1": 0.0012, "nurbs_2": 3e-05}


@needs_openscad
def test_csg_judge_scores_the_ground_truth_one_and_a_moved_copy_less(tmp_path):
    gt_scad = os.path.join(BENCH, "crosses.gt.scad")
    stl = str(tmp_path / "gt.stl")
    subprocess.run(["openscad", "-o", stl, gt_scad], check=True, capture_output=True,
                   timeout=300)
    gt = rj.read_stl(stl)
    assert rj.volume_iou(gt, gt, 96) == 1.0
    moved = gt + [0.02 * rj.bbox_diagonal(gt), 0, 0]  # bench_range's `shifted`
    assert rj.volume_iou(moved, gt, 96) < 0.9


@needs_openscad
def test_blade_scad_stand_in_renders_close_to_the_true_surface(tmp_path):
    gt = pj.patch_from_gt(blade_gt())
    scad, stl = tmp_path / "blade.scad", str(tmp_path / "blade.stl")
    patch = pj.patch_from_leaf(pj.gt_as_leaf(blade_gt(), "exact"))
    scad.write_text(pj.polyhedron_scad(patch, cells=(60, 20)))
    subprocess.run(["openscad", "-o", stl, str(scad)], check=True, capture_output=True,
                   timeout=300)
    reported = pj.header_deviations(scad.read_text())["nurbs_1"]
    top = pj.top_deviation(rj.read_stl(stl), gt, pixel=0.25)
    assert top["scad_top_coverage"] == 1.0
    assert top["scad_top_dev_max"] <= reported  # the header's bound holds on the render


@needs_freecad
@needs_data
def test_step_of_the_ground_truth_is_one_valid_solid_with_a_bspline_face(tmp_path):
    doc = tmp_path / "blade.json"
    doc.write_text(json.dumps(pj.result_document(pj.gt_as_leaf(blade_gt(), "exact"), "gt")))
    step = tmp_path / "blade.step"
    pj.write_step(str(doc), str(step))
    chk = pj.step_check(str(step))
    assert chk["passed"], chk
    # top, floor, four walls; the volume of the true solid (bench_points' 200 x 60 midpoint sum)
    assert chk["faces"] == 6 and chk["mesh_volume"] == pytest.approx(12879.4, rel=1e-3)
    (tmp_path / "bad.step").write_text("ISO-10303-21;\nEND-ISO-10303-21;\n")
    try:
        assert not pj.step_check(str(tmp_path / "bad.step"))["passed"]
    except RuntimeError:
        pass  # FreeCAD refused to read it at all: as good a "no"


STAND_IN_CLI = r'''#!/usr/bin/python3
# A stand-in for `csgfit points` (the contract's command line): the ground truth as its .scad,
# .json and .step, a summary line on stderr.
import json, os, shutil, sys
sys.path.insert(0, %r)
import points_judge as pj
args = sys.argv[1:]
assert args[0] == "points" and "--time" in args and "--seed" in args, args
cloud = args[1]
outs = {os.path.splitext(args[i + 1])[1]: args[i + 1] for i, a in enumerate(args) if a == "-o"}
bench = os.path.dirname(cloud)
name = os.path.basename(cloud).rsplit(".", 1)[0]
gt = name.rsplit("_", 1)[0]
if gt == "blade":
    leaf = pj.gt_as_leaf(json.load(open(os.path.join(bench, "blade.gt.json"))), "exact")
    json.dump(pj.result_document(leaf, cloud), open(outs[".json"], "w"))
    open(outs[".scad"], "w").write(pj.polyhedron_scad(pj.patch_from_leaf(leaf), cells=(60, 20)))
    pj.write_step(outs[".json"], outs[".step"])
else:
    shutil.copyfile(os.path.join(bench, gt + ".gt.scad"), outs[".scad"])
print("csgfit: 1 primitives (stand-in); 0.01 s", file=sys.stderr)
'''


@needs_openscad
@needs_freecad
def test_bench_points_runs_end_to_end_with_a_stand_in_cli(tmp_path):
    """The driver's real path (command line, fit, render, .csg count, deviation, STEP, the
    comparison's runs, JSON) on blade_top with a stand-in for the solver."""
    proc, doc = stand_in.run_driver(tmp_path, STAND_IN_CLI % os.path.join(REPO, "scripts"),
                                    "bench_points.py", ["--models", "blade_top", "--formats",
                                                        "xyz", "--time", "1"])
    assert proc.returncode == 0, proc.stderr
    assert [r["variant"] for r in doc["runs"]] == ["default", "islands1", "hill"]
    assert "--islands 1" in doc["runs"][1]["command"]
    assert "--search hill" in doc["runs"][2]["command"]
    for run in doc["runs"]:
        assert run["status"] == "ok" and run["step_ok"] is True, run
        assert run["dev_max"] < 1e-9 and run["scad_top_dev_max"] <= run["scad_header_dev"]
    assert all(a["ok"] in (True, None) for a in doc["acceptance"])
    assert "| blade_top_xyz |" in proc.stdout and "--search hill" in proc.stdout
