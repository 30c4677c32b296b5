"""scripts/scad_count.py and scripts/random_parts.py: what bench_3d.py's operation columns and
the random set stand on. Counting must agree with the printed set's manifest, and a seed must
give the same programs; neither needs the build or OpenSCAD."""

import json
import os
import re
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "scripts"))
import random_parts  # noqa: E402
import scad_count  # noqa: E402

PRINTED = os.path.join(os.path.dirname(REPO), "shared", "benchmarks", "3d", "printed")


def test_counts_operations_and_prisms_not_comments():
    text = """
    // difference() in a comment, /* union() */ too
    difference() {
        linear_extrude(height = 2) hull() { circle(d = 4); translate([9, 0]) circle(d = 4); }
        cylinder(h = 3, r = fn_r(1.5), $fn = 6);   // a nut trap
        cylinder($fn = 0, $fa = 6, $fs = 0.25, h = 3, r = 1);
        circle($fn = 60, r = 2);
        circle($fn = 8, r = 2);
    }
    """
    assert scad_count.scad_operations(text) == {
        "difference": 1, "linear_extrude": 1, "hull": 1, "fn_prism": 2}
    assert scad_count.scad_leaves(text) == 6
    assert scad_count.ops_text(scad_count.scad_operations(text)) == "L1 H1 D1 P2"
    assert scad_count.ops_text({}) == "none"


@pytest.mark.skipif(not os.path.isdir(PRINTED), reason="no ../shared/benchmarks/3d/printed")
def test_agrees_with_the_printed_manifest():
    with open(os.path.join(PRINTED, "manifest.json")) as f:
        models = json.load(f)["models"]
    for m in models:
        with open(os.path.join(PRINTED, m["gt"])) as f:
            text = f.read()
        ops = scad_count.scad_operations(text)
        assert {k: ops.get(k) for k in m["gt_operations"]} == m["gt_operations"], m["name"]
        assert scad_count.scad_leaves(text) == m["gt_primitives"], m["name"]


def programs(seed, n):
    draw = random_parts.Draw(seed)
    return ["\n".join(random_parts.emit(random_parts.random_part(draw)[1])) for _ in range(n)]


def test_random_programs_are_deterministic_and_on_the_raster():
    first = programs(7, 40)
    assert first == programs(7, 40)
    assert first != programs(8, 40)
    for text in first:
        assert scad_count.scad_leaves(text) >= 1
        for number in re.findall(r"(?<![$\w])-?\d+(?:\.\d+)?", text):
            if float(number) not in (45, 90, 180, -90):
                assert float(number) * 2 == int(float(number) * 2), (number, text)


def tetrahedron(offset=0.0):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float) + offset
    return v[np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])]


def test_solid_problem_finds_open_edges_and_extra_shells():
    assert random_parts.solid_problem(tetrahedron()) is None
    assert random_parts.solid_problem(tetrahedron()[:3]) == "3 edges not shared by two triangles"
    two = np.concatenate([tetrahedron(), tetrahedron(5.0)])
    assert random_parts.solid_problem(two) == "2 shells"
