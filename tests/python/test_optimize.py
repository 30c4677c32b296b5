"""csgfit.optimize and `csgfit optimize` / `csgfit inflate` on OpenSCAD programs: the same solid
(OpenSCAD's rendering, voxelised here), never larger, bad input refused in one line."""

import os
import subprocess
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("CSGFIT_BUILD_DIR", os.path.join(REPO, "build"))
CLI = os.path.join(BUILD, "bin", "csgfit")
sys.path.insert(0, os.path.join(BUILD, "python"))
sys.path.insert(0, os.path.join(REPO, "scripts"))
import csgfit  # noqa: E402
import stl_voxelize  # noqa: E402
from bench_3d import openscad_stl, volume_iou  # noqa: E402

LOCK = os.path.join(os.path.dirname(REPO), "shared", "benchmarks", "3d", "inversecsg", "lock", "csg.scad")
REDUNDANT = """
difference() {
  union() {
    cube([20, 16, 10]);
    translate([4, 4, 5]) sphere(r = 2, $fn = 24);
    intersection() { cube([20, 16, 10]); translate([30, 0, 0]) cube(4); }
  }
  translate([10, 8, -5]) cylinder(h = 20, r = 3, $fn = 24);
  translate([50, 50, 50]) cube(2);
}
"""


def rendered(path, tmp_path, name):
    stl = str(tmp_path / (name + ".stl"))
    openscad_stl(path, stl, 300)
    return stl_voxelize.read_stl(stl)


def test_redundant_parts_go_and_the_solid_stays(tmp_path):
    src = tmp_path / "part.scad"
    src.write_text(REDUNDANT)
    r = csgfit.optimize(str(src))
    assert r.primitives_before == 6 and r.primitives_after == 2
    assert r.size_after < r.size_before
    out = r.save(tmp_path / "part.opt.scad")
    value, _ = volume_iou(rendered(str(src), tmp_path, "a"), rendered(out, tmp_path, "b"), 64)
    assert value >= 0.999


def test_inflated_lock_comes_back_to_its_size(tmp_path):
    if not os.path.exists(LOCK):
        pytest.skip("benchmark not present")
    infl, out = str(tmp_path / "lock.infl.csg"), str(tmp_path / "lock.opt.csg")
    subprocess.run([CLI, "inflate", LOCK, "-o", infl, "--steps", "10", "--seed", "3", "-q"], check=True)
    proc = subprocess.run([CLI, "optimize", infl, "-o", out], capture_output=True, text=True, check=True)
    assert "csgfit: size" in proc.stderr
    base = csgfit.optimize(LOCK)
    again = csgfit.optimize(out)
    assert again.primitives_before <= base.primitives_before  # 5 primitives, as drawn
    value, _ = volume_iou(rendered(LOCK, tmp_path, "lock"), rendered(out, tmp_path, "opt"), 64)
    assert value >= 0.999


def test_same_seed_same_program(tmp_path):
    a = csgfit.optimize(REDUNDANT_CSG(tmp_path), method="ga", seed=4)
    b = csgfit.optimize(REDUNDANT_CSG(tmp_path), method="ga", seed=4)
    assert a.csg == b.csg


def REDUNDANT_CSG(tmp_path):
    src = tmp_path / "r.scad"
    src.write_text(REDUNDANT)
    return str(src)


@pytest.mark.parametrize("text, message", [
    ("cube([1, 1, 1]", "openscad"),
    ("multmatrix([[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) cube(1);", "singular"),
    ("intersection() { cube(1); translate([5, 0, 0]) cube(1); }", "empty"),
])
def test_bad_programs_are_one_line_and_exit_2(tmp_path, text, message):
    src = tmp_path / "bad.scad"
    src.write_text(text)
    out = tmp_path / "out.scad"
    proc = subprocess.run([CLI, "optimize", str(src), "-o", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and message in proc.stderr.lower(), proc.stderr
    assert not out.exists()


def test_unknown_method_and_bad_weight_are_refused():
    with pytest.raises(csgfit.InputError):
        csgfit.optimize("x.csg", method="magic")
    with pytest.raises(csgfit.InputError):
        csgfit.optimize("x.csg", proximity_weight=float("nan"))


@pytest.mark.parametrize("make, message", [
    (lambda: "union() {" * 100000 + "cube(size = 1);" + "}" * 100000, "deeper than"),
    (lambda: "union() {\n" + "cube(size = [1, 1, 1], center = false);\n" * 1000000 + "}\n", "primitive calls"),
    (lambda: "union() {\n" + "".join("multmatrix([[1, 0, 0, %d], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) "
                                     "{ cube(size = 1); }\n" % i for i in range(6000)) + "}\n", "distinct primitives"),
])
def test_absurd_trees_are_refused_quickly_in_one_line(tmp_path, make, message):
    src = tmp_path / "absurd.csg"
    src.write_text(make())
    out = tmp_path / "out.csg"
    proc = subprocess.run([CLI, "optimize", str(src), "-o", str(out)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and message in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert not out.exists()


def test_a_wide_union_of_copies_comes_back_as_one_primitive(tmp_path):
    src = tmp_path / "copies.csg"
    src.write_text("union() {\n" + "cube(size = [1, 2, 3], center = false);\n" * 50000 + "}\n")
    r = csgfit.optimize(str(src))
    assert r.primitives_before == 50000 and r.primitives_after == 1
