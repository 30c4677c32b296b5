"""Tests of the csgfit module's range fit (fit_range, fit_range_points: seed 002) on the object of
Lin & Chen's Fig. 10 in ../shared/benchmarks/range and on points the tests sample from a known
part (run with /usr/bin/python3 -m pytest tests/python)."""

import json
import os
import shutil

import numpy as np
import pytest

from built import BENCHMARKS, csgfit  # noqa: E402
BENCH = os.path.join(BENCHMARKS, "range")

ORTHO = os.path.join(BENCH, "object_b_ortho.png")
PINHOLE = os.path.join(BENCH, "object_b_pinhole.png")
needs_bench = pytest.mark.skipif(not os.path.exists(ORTHO), reason=f"needs {BENCH}")


def seed_002_graph(graph):
    """Checks the graph of object_b (the paper's Fig. 10): a block (order 1) minus a large
    cylinder (order 2, negative), two small cylinders appended inside the cut (order 3,
    positive), and the cylinder on top as a subobject of its own. Returns the nodes by role."""
    assert graph.subobjects == 2 and len(graph.nodes) == 5
    block = next(i for i, n in enumerate(graph.nodes) if n.kind == "box")
    b = graph.nodes[block]
    assert b.order == 1 and b.positive
    main = b.subobject
    assert [graph.nodes[i].kind for i in graph.subobject_nodes(main)] == ["box"] + ["cylinder"] * 3
    cut = [i for i in graph.subobject_nodes(main) if graph.nodes[i].order == 2]
    assert len(cut) == 1 and graph.nodes[cut[0]].sign == "negative"
    small = [i for i in graph.subobject_nodes(main) if graph.nodes[i].order == 3]
    assert len(small) == 2 and all(graph.nodes[i].positive for i in small)
    top = [i for i, n in enumerate(graph.nodes) if n.subobject != main]
    assert len(top) == 1
    t = graph.nodes[top[0]]
    assert t.kind == "cylinder" and t.order == 1 and t.positive
    # Radii of the model (a block 3 x 3 x 1.5, a radius-2.5 cut, radius-0.5 and 0.75 cylinders).
    assert graph.nodes[cut[0]].primitive.r == pytest.approx(2.5, abs=0.05)
    assert all(graph.nodes[i].primitive.r == pytest.approx(0.5, abs=0.03) for i in small)
    assert t.primitive.r == pytest.approx(0.75, abs=0.03)
    arcs = {(a.from_, a.to): a.kind for a in graph.arcs}
    assert arcs.get((block, cut[0])) == "subtracting"
    assert all(arcs.get((cut[0], i)) == "appending" for i in small)
    # Every face of object_b is seen: no cut is a conjecture.
    assert not any(n.conjectured for n in graph.nodes)
    return block, cut[0], small, top[0]


@needs_bench
def test_object_b_gives_the_seed_002_graph_and_its_outputs(tmp_path):
    seen = []
    r = csgfit.fit_range(ORTHO, time=20, seed=1, progress=lambda p: seen.append(p.fraction))
    assert isinstance(r, csgfit.RangeFitResult) and isinstance(r, csgfit.Result)
    assert seen and seen[-1] == 1.0 and all(0 <= f <= 1 for f in seen)
    assert r.stats.primitives == 5 and r.tree.count() == 5
    seed_002_graph(r.precedence_graph)
    assert len(r.views) == 1 and r.views[0].source == ORTHO
    assert r.views[0].silhouette_iou > 0.99 and r.views[0].depth_error < 0.005 * r.diagonal
    assert r.stats.iou == pytest.approx(r.views[0].silhouette_iou)
    assert len(r.patches) >= 5 and {p.kind for p in r.patches} >= {"plane", "cylinder"}
    labels = r.patch_of_point
    assert labels.ndim == 1 and labels.max() == len(r.patches) - 1 and labels.min() >= -1
    report = r.report()
    assert report.startswith("There are 2 subobjects:") and "NEGATIVE" in report
    doc = r.to_dict()
    assert doc == r.document and doc["dimension"] == 3
    assert len(doc["precedence_graph"]["nodes"]) == 5
    assert all(n["conjectured"] is False for n in doc["precedence_graph"]["nodes"])
    assert r.sources == [ORTHO]

    for ext in ("json", "scad"):
        out = r.save(tmp_path / f"object_b.{ext}")
        assert os.path.getsize(out) > 200
    assert json.load(open(tmp_path / "object_b.json"))["tree"] == doc["tree"]
    assert "cylinder(" in (tmp_path / "object_b.scad").read_text()
    png = r.save_preview(tmp_path / "preview.png")
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(csgfit.InputError, match="expected .scad"):
        r.save(tmp_path / "object_b.stl")


@needs_bench
@pytest.mark.parametrize("image, edge", [("three_cuboids_pinhole.png", 4.831), ("six_cuboids_pinhole.png", 3.224),
                                         ("nine_cuboids_pinhole.png", 2.580)])
def test_cubes_partly_hidden_are_drawn_as_cubes(image, edge):
    # Behind three_cuboids' slab only a corner of the 4.83 cube shows, and seed 002's smallest
    # extents leave a sliver; nine_cuboids' 2.58 cube shows a little more; six_cuboids' 3.22
    # cube has a hidden side the search leaves long. The designer drew cubes. The time lets
    # every fit converge: the same tree on any machine.
    r = csgfit.fit_range(os.path.join(BENCH, image), time=100, seed=1)
    boxes = [n.primitive.size for n in r.precedence_graph.nodes if n.kind == "box" and n.positive]
    assert any(all(abs(v - edge) < 0.03 * edge for v in s) for s in boxes), boxes


@needs_bench
def test_two_views_in_one_call_are_merged():
    r = csgfit.fit_range([ORTHO, PINHOLE], time=20, seed=1)
    assert r.sources == [ORTHO, PINHOLE]
    assert [v.source for v in r.views] == [ORTHO, PINHOLE]
    assert all(v.silhouette_iou > 0.98 for v in r.views)
    seed_002_graph(r.precedence_graph)
    # Points of both views are labelled: more than one 192 x 192 view can hold.
    assert len(r.patch_of_point) > 192 * 192 // 4


@needs_bench
def test_intrinsics_stand_in_for_a_missing_sidecar(tmp_path):
    with open(os.path.join(BENCH, "object_b_ortho.json")) as f:
        sidecar = json.load(f)
    bare = tmp_path / "object_b.png"
    shutil.copy(ORTHO, bare)
    with pytest.raises(csgfit.InputError) as e:
        csgfit.fit_range(bare, time=5)
    assert "\n" not in str(e.value) and "object_b.png" in str(e.value)
    # With the sidecar's own numbers given (camera_to_world then defaults to the identity),
    # the same part is fitted in the camera's frame.
    r = csgfit.fit_range(bare, time=20, pixel_size=sidecar["pixel_size"],
                         depth_unit=sidecar["depth_unit"])
    assert r.stats.primitives == 5 and r.precedence_graph.subobjects == 2


def box_and_cylinder(n=6000, seed=0):
    """Points on the surface of a 4 x 3 x 2 block (corner at the origin) with a radius-0.8,
    height-1.5 cylinder standing on its top at (1.5, 1.5), and their outward normals."""
    rng = np.random.default_rng(seed)
    faces = []  # (points, normal) per face, points drawn uniformly over the face's area
    for axis, size in ((0, 4.0), (1, 3.0), (2, 2.0)):
        others = [a for a in range(3) if a != axis]
        dims = [(4.0, 3.0, 2.0)[a] for a in others]
        for side in (0.0, size):
            m = int(n * dims[0] * dims[1] / 52.0)
            p = np.zeros((m, 3))
            p[:, others[0]] = rng.uniform(0, dims[0], m)
            p[:, others[1]] = rng.uniform(0, dims[1], m)
            p[:, axis] = side
            normal = np.zeros(3)
            normal[axis] = 1.0 if side else -1.0
            if axis == 2 and side:  # the block's top, less the cylinder's footprint
                keep = np.hypot(p[:, 0] - 1.5, p[:, 1] - 1.5) > 0.8
                p = p[keep]
            faces.append((p, np.tile(normal, (len(p), 1))))
    m = int(n * 2 * np.pi * 0.8 * 1.5 / 52.0)
    a, z = rng.uniform(0, 2 * np.pi, m), rng.uniform(2.0, 3.5, m)
    side = np.stack([1.5 + 0.8 * np.cos(a), 1.5 + 0.8 * np.sin(a), z], 1)
    faces.append((side, np.stack([np.cos(a), np.sin(a), np.zeros(m)], 1)))
    m = int(n * np.pi * 0.64 / 52.0)
    rr, a = 0.8 * np.sqrt(rng.uniform(0, 1, m)), rng.uniform(0, 2 * np.pi, m)
    cap = np.stack([1.5 + rr * np.cos(a), 1.5 + rr * np.sin(a), np.full(m, 3.5)], 1)
    faces.append((cap, np.tile([0.0, 0.0, 1.0], (m, 1))))
    return np.concatenate([f[0] for f in faces]), np.concatenate([f[1] for f in faces])


def check_box_and_cylinder(r):
    leaves = [n for n in r.tree.walk() if isinstance(n, csgfit.Primitive3D)]
    assert sorted(leaf.type for leaf in leaves) == ["box", "cylinder"], r.tree
    box = next(leaf for leaf in leaves if leaf.type == "box")
    cyl = next(leaf for leaf in leaves if leaf.type == "cylinder")
    assert sorted(box.size) == pytest.approx([2.0, 3.0, 4.0], abs=0.08)
    assert box.center == pytest.approx([2.0, 1.5, 1.0], abs=0.05)
    assert cyl.r == pytest.approx(0.8, abs=0.03) and cyl.h == pytest.approx(1.5, abs=0.05)
    assert cyl.center[:2] == pytest.approx([1.5, 1.5], abs=0.03)
    assert all(n.positive for n in r.precedence_graph.nodes)
    assert r.views == []  # no camera: nothing to re-see


def test_fit_points_finds_a_sampled_box_and_cylinder():
    points, normals = box_and_cylinder()
    check_box_and_cylinder(csgfit.fit_range_points(points, time=20, seed=1))
    r = csgfit.fit_points(points, normals, search="range", time=20, seed=1)
    check_box_and_cylinder(r)
    assert not r.has_preview
    with pytest.raises(csgfit.InputError, match="no preview"):
        r.save_preview("/tmp/never.png")


def test_fit_points_reads_an_xyz_file(tmp_path):
    points, normals = box_and_cylinder(seed=2)
    path = tmp_path / "part.xyz"
    np.savetxt(path, np.hstack([points, normals]))
    check_box_and_cylinder(csgfit.fit_range_points(path, time=20, seed=1))


def test_same_seed_same_tree():
    points, _ = box_and_cylinder(seed=3)
    a = csgfit.fit_range_points(points, time=20, seed=7, threads=2)
    b = csgfit.fit_range_points(points, time=20, seed=7, threads=2)
    assert a.document["tree"] == b.document["tree"]
    assert a.document["precedence_graph"] == b.document["precedence_graph"]


@needs_bench
def test_a_fit_that_converges_gives_the_same_tree_at_any_time_limit():
    # tower_of_hanoi's noisy view converges in about 9 s; with every stage stopped at a fixed
    # share of --time, at 20 s its first polish was cut at 4 s, wherever it had got to, and the
    # tree changed from run to run (volume IoU 0.80 or 0.96).
    image = os.path.join(BENCH, "tower_of_hanoi_ortho_noisy.png")
    a = csgfit.fit_range(image, time=20, seed=1)
    b = csgfit.fit_range(image, time=100, seed=1)
    assert a.document["tree"] == b.document["tree"]


def one_line_input_error(call, *words):
    with pytest.raises(csgfit.InputError) as e:
        call()
    text = str(e.value)
    assert isinstance(e.value, ValueError) and text and "\n" not in text, text
    for w in words:
        assert w in text, text
    return text


@needs_bench
def test_bad_intrinsics_are_one_line():
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, pixel_size=float("nan")), "pixel_size")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, fx=0, fy=500), "fx", "[0.001, 1e+07]")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, fx=-3.0, fy=500), "fx")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, depth_unit="a lot"), "depth_unit")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, cx=float("inf")), "cx")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, time=0), "time")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, time="long"), "time")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, seed=1.5), "seed")
    one_line_input_error(lambda: csgfit.fit_range(ORTHO, primitives="box,blob"), "blob")


def test_bad_inputs_are_one_line(tmp_path):
    one_line_input_error(lambda: csgfit.fit_range([]), "no input")
    one_line_input_error(lambda: csgfit.fit_range(tmp_path / "missing.png"), "missing.png")
    one_line_input_error(lambda: csgfit.fit_range(42), "path")
    one_line_input_error(lambda: csgfit.fit_range_points(np.zeros((100, 2))), "(n, 3)", "(100, 2)")
    one_line_input_error(lambda: csgfit.fit_range_points(np.zeros((4, 3, 1))), "(n, 3)")
    one_line_input_error(lambda: csgfit.fit_range_points([["a", "b", "c"]]), "points")
    points, normals = box_and_cylinder(n=2000)
    nan = points.copy()
    nan[17, 1] = np.nan
    one_line_input_error(lambda: csgfit.fit_range_points(nan), "points", "17", "finite")
    one_line_input_error(lambda: csgfit.fit_range_points(points, normals[:10]), "normals", "10")
    one_line_input_error(lambda: csgfit.fit_range_points(points[:6]), "too few points")
    one_line_input_error(lambda: csgfit.fit_range_points(tmp_path / "part.stl"), "fit_range")
    one_line_input_error(lambda: csgfit.fit_range_points(points, progress=3), "progress")
    one_line_input_error(lambda: csgfit.fit_range_points(points, cancel=True), "CancelToken")


def test_cancel_returns_the_tree_so_far():
    points, _ = box_and_cylinder(seed=4)
    token = csgfit.CancelToken()
    token.cancel()
    r = csgfit.fit_range_points(points, time=20, cancel=token)
    assert r.stats.stop_reason == "cancelled"
