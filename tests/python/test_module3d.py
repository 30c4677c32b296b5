"""Tests of the csgfit module's 3D fit (fit_voxels, fit_mesh, voxelize) on voxel shapes and a
mesh the tests make themselves (run with /usr/bin/python3 -m pytest tests/python)."""

import json
import struct
import threading
import time

import numpy as np
import pytest

from built import csgfit  # noqa: E402


def box_minus_sphere(n=36):
    """[i, j, k] = voxel (x, y, z): a 28 x 20 x 16 block with a spherical pocket."""
    i, j, k = np.mgrid[0:n, 0:n, 0:n] + 0.5
    block = (np.abs(i - 18) < 14) & (np.abs(j - 18) < 10) & (np.abs(k - 18) < 8)
    pocket = (i - 26) ** 2 + (j - 18) ** 2 + (k - 26) ** 2 < 8 ** 2
    return block & ~pocket


def ball(n=30, r=11.0):
    i, j, k = np.mgrid[0:n, 0:n, 0:n] + 0.5
    return (i - n / 2) ** 2 + (j - n / 2) ** 2 + (k - n / 2) ** 2 < r * r


def iou(a, b):
    return np.logical_and(a, b).sum() / np.logical_or(a, b).sum()


def test_voxel_fit_returns_the_3d_document_and_its_voxels():
    vox = box_minus_sphere()
    seen = []
    r = csgfit.fit_voxels(vox, origin=(10.0, -5.0, 2.0), voxel_size=0.5, time=30, seed=1,
                          threads=2, progress=lambda p: seen.append(p.fraction))
    assert seen and all(0 <= f <= 1 for f in seen)
    assert r.stats.iou >= 0.98 and r.stats.primitives <= 4
    assert r.stats.stop_reason == "converged"
    doc = r.to_dict()
    assert doc["schema"] == "csgfit/1" and doc["dimension"] == 3
    assert doc["grid"] == {"nx": 36, "ny": 36, "nz": 36, "origin": [10.0, -5.0, 2.0],
                           "voxel_size": 0.5, "frame": [1.0, 0.0, 0.0, 0.0]}
    assert json.loads(r.to_json()) == doc
    assert doc["tree"]["op"] == "difference"
    assert doc["tree"]["children"][0]["type"] == "box"
    # The block's centre in model units: origin + 18 voxels * 0.5.
    assert doc["tree"]["children"][0]["center"] == pytest.approx([19.0, 4.0, 11.0], abs=0.3)
    target, raster = r.target(), r.raster()
    assert target.shape == raster.shape == vox.shape and raster.dtype == np.bool_
    assert np.array_equal(target, vox)
    assert iou(raster, vox) == pytest.approx(r.stats.iou, abs=1e-9)
    assert r.volume() == pytest.approx(raster.sum() * 0.125)
    assert "difference()" in r.to_scad() or "difference" in r.to_scad()


def test_ball_is_one_sphere_or_ellipsoid():
    r = csgfit.fit_voxels(ball(), time=20, seed=2, threads=2)
    assert r.stats.iou >= 0.97
    assert r.stats.primitives == 1 and r.tree.type in ("sphere", "ellipsoid")


def test_same_seed_same_tree():
    vox = box_minus_sphere(30)
    a = csgfit.fit_voxels(vox, time=30, seed=7, threads=2)
    b = csgfit.fit_voxels(vox, time=30, seed=7, threads=2)
    assert a.stats.stop_reason == b.stats.stop_reason == "converged"
    assert a.tree == b.tree


def write_stl(path, vertices, triangles):
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(triangles)))
        for t in triangles:
            f.write(struct.pack("<12fH", 0, 0, 0, *vertices[t[0]], *vertices[t[1]],
                                *vertices[t[2]], 0))


def cube_mesh(lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)], float)
    # Outward-facing (counter-clockwise seen from outside).
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return v, t


def test_mesh_arrays_and_file_give_the_same_fit(tmp_path):
    v, t = cube_mesh((1, 2, 3), (21, 12, 8))
    path = tmp_path / "slab.stl"
    write_stl(path, v, t)
    a = csgfit.fit_mesh((v, t), resolution=48, time=20, seed=1, threads=2)
    b = csgfit.fit_mesh(str(path), resolution=48, time=20, seed=1, threads=2)
    assert b.source == "slab.stl" and a.source == ""
    assert a.tree == b.tree and a.warning == ""
    assert a.stats.iou >= 0.99 and a.tree.type == "box"
    assert a.volume() == pytest.approx(20 * 10 * 5, rel=0.1)
    vox, origin, size, warning = csgfit.voxelize(v, t, resolution=48)
    assert vox.shape[0] == 48 + 2 and size == pytest.approx(20 / 48)
    assert np.array_equal(vox, a.target()) and origin == pytest.approx(a.origin)
    lv, lt = csgfit.load_mesh(path)
    assert lv.shape == (8, 3) and lt.shape == (12, 3)


def test_open_mesh_is_fitted_with_a_warning():
    v, t = cube_mesh((0, 0, 0), (10, 10, 10))
    r = csgfit.fit_mesh((v, t[:-1]), resolution=32, time=10, seed=1, threads=2)
    assert r.warning and r.stats.iou >= 0.95


def test_cancel_stops_a_long_fit_within_a_second():
    rng = np.random.default_rng(3)
    i, j, k = np.mgrid[0:96, 0:96, 0:96] + 0.5
    vox = np.zeros((96, 96, 96), bool)
    for _ in range(30):  # many blobs: nowhere near convergence in a second
        c, rad = rng.uniform(15, 81, 3), rng.uniform(5, 14)
        vox ^= (i - c[0]) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2 < rad * rad
    token = csgfit.CancelToken()
    stamp = []
    threading.Timer(1.0, lambda: (stamp.append(time.monotonic()), token.cancel())).start()
    r = csgfit.fit_voxels(vox, time=60, threads=2, cancel=token)
    latency = time.monotonic() - stamp[0]
    assert r.stats.stop_reason == "cancelled"
    assert latency < 1.0, latency
    assert r.stats.primitives >= 1  # the best tree so far


def test_progress_returning_false_cancels():
    r = csgfit.fit_voxels(box_minus_sphere(), time=30, threads=2, progress=lambda p: False)
    assert r.stats.stop_reason == "cancelled"


@pytest.mark.parametrize("call, match", [
    (lambda: csgfit.fit_voxels(np.zeros((8, 8, 8), bool)), "no solid"),
    (lambda: csgfit.fit_voxels(np.ones((8, 8), bool)), "3D voxel array"),
    (lambda: csgfit.fit_voxels(np.full((4, 4, 4), np.nan)), "NaN"),
    (lambda: csgfit.fit_voxels(ball(), voxel_size=0), "voxel_size"),
    (lambda: csgfit.fit_voxels(ball(), origin=(0, 0)), "origin"),
    (lambda: csgfit.fit_voxels(ball(), primitives="box,hexagon"), "hexagon"),
    (lambda: csgfit.fit_voxels(ball(), time=0), "time"),
    (lambda: csgfit.fit_mesh("/nonexistent/part.stl"), "part.stl"),
    (lambda: csgfit.fit_mesh("/tmp/part.xyz"), "unknown input format"),
    (lambda: csgfit.fit_mesh((np.zeros((3, 3)), np.array([[0, 1, 5]]))), "vertex 5"),
    (lambda: csgfit.fit_mesh((np.full((3, 3), np.nan), np.array([[0, 1, 2]]))), "not finite"),
    (lambda: csgfit.fit_mesh((np.zeros((3, 2)), np.array([[0, 1, 2]]))), r"\(n, 3\)"),
    (lambda: csgfit.fit_mesh(42), "path or a"),
])
def test_bad_input_raises_input_error(call, match):
    with pytest.raises(csgfit.InputError, match=match):
        call()


def test_bad_file_contents(tmp_path):
    bad = tmp_path / "fake.stl"
    bad.write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 100)
    with pytest.raises(csgfit.InputError, match="fake.stl"):
        csgfit.fit_mesh(str(bad))
    npy = tmp_path / "flat.npy"
    np.save(npy, np.ones((4, 4), bool))
    with pytest.raises(csgfit.InputError, match="flat.npy"):
        csgfit.fit_mesh(str(npy))


def test_voxel_file_and_voxel_array_give_the_same_kind_of_result(tmp_path):
    path = tmp_path / "ball.npy"
    np.save(path, ball())
    from_file = csgfit.fit_mesh(str(path), time=20, seed=2, threads=2)
    from_array = csgfit.fit_voxels(ball(), time=20, seed=2, threads=2)
    assert from_file.source == "ball.npy" and from_file.voxel_size == 1.0
    assert from_file.origin == (0.0, 0.0, 0.0)
    assert np.array_equal(from_file.target(), ball()) and from_file.stats.iou >= 0.97
    assert type(from_file) is type(from_array) is csgfit.FitResult3D
    assert isinstance(from_file.tree, csgfit.Primitive3D)
    # Fitted as it is, on its own grid: the same tree and the same document.
    assert from_file.tree == from_array.tree
    doc_file, doc_array = from_file.to_dict(), from_array.to_dict()
    for d in (doc_file, doc_array):
        d.pop("source")
        d["stats"].pop("seconds")
    assert doc_file == doc_array


def json_leaves(d):
    if "op" in d:
        return [leaf for c in d["children"] for leaf in json_leaves(c)]
    return [d]


def test_3d_tree_objects_agree_with_the_json_document():
    r = csgfit.fit_voxels(box_minus_sphere(), origin=(10.0, -5.0, 2.0), voxel_size=0.5,
                          time=30, seed=1, threads=2)
    doc = r.document
    assert r.tree.to_dict() == doc["tree"]
    leaves = [n for n in r.tree.walk() if n.op == "primitive"]
    assert len(leaves) == r.tree.count() == r.stats.primitives == len(json_leaves(doc["tree"]))
    for leaf, d in zip(leaves, json_leaves(doc["tree"])):
        assert isinstance(leaf, csgfit.Primitive3D) and leaf.type == d["type"]
        assert list(leaf.center) == d["center"] and list(leaf.rotation) == d["rotation"]
        for name in csgfit.SIZE_FIELDS_3D[leaf.type]:
            value = getattr(leaf, name)
            assert (list(value) if isinstance(value, tuple) else value) == d[name], name
    # Model units: the block is 28 x 20 x 16 voxels of 0.5, centred at origin + 18 voxels.
    block, pocket = r.tree.children
    assert r.tree.op == "difference" and block.type == "box"
    assert sorted(block.size) == pytest.approx([8, 10, 14], abs=0.3)
    assert block.center == pytest.approx((19.0, 4.0, 11.0), abs=0.3)
    assert pocket.type in ("sphere", "ellipsoid")
    assert str(r.tree).startswith("difference(box(center=(19")


def test_a_polygonal_cylinder_shows_its_sides():
    # The 3D document's leaves as csgfit.tree makes them: a hexagonal nut trap and a round hole.
    doc = {"op": "difference", "children": [
        {"type": "cylinder", "center": [0, 0, 0], "rotation": [1, 0, 0, 0],
         "euler_deg": [0, 0, 0], "r": 3, "h": 5, "sides": 6},
        {"type": "cylinder", "center": [0, 0, 0], "rotation": [1, 0, 0, 0],
         "euler_deg": [0, 0, 0], "r": 1, "h": 9}]}
    tree = csgfit.tree.tree_from_json3d(doc)
    nut, hole = tree.children
    assert (nut.sides, hole.sides) == (6, None)
    assert tree.to_dict() == doc
    assert "sides=6" in str(nut) and "sides" not in str(hole)


def rounded_plate():
    """[i, j, k] = voxel (x, y, z): a plate 30 x 20 x 8 whose edges along z are rounded with
    radius 6, centred at (20, 14, 6)."""
    i, j, k = np.mgrid[0:40, 0:28, 0:12] + 0.5
    qx, qy = np.abs(i - 20) - 9, np.abs(j - 14) - 4
    section = np.hypot(np.maximum(qx, 0), np.maximum(qy, 0)) + np.minimum(np.maximum(qx, qy), 0)
    return (section <= 6) & (np.abs(k - 6) <= 4)


def test_a_rounded_box_is_fitted_when_named_and_shows_its_corner():
    plate = rounded_plate()
    r = csgfit.fit_voxels(plate, primitives="box,rounded_box", k=60, time=20, threads=1)
    assert r.stats.iou > 0.99 and r.stats.primitives == 1
    leaf = r.tree
    assert leaf.type == "rounded_box"
    assert leaf.corner == pytest.approx(6, abs=0.75)
    assert leaf.size == pytest.approx((30, 20, 8), abs=0.75)
    assert f"corner={leaf.corner:.4g}" in str(leaf)
    assert leaf.to_dict() == r.document["tree"]
    # Boxes only (the default): no rounded box, and a worse fit.
    boxes = csgfit.fit_voxels(plate, primitives="box", k=60, time=20, threads=1)
    assert "rounded_box" not in str(boxes.tree)
    assert boxes.stats.iou < r.stats.iou - 0.01
    assert "rounded_box" in csgfit.PRIMITIVE_TYPES_3D


def test_a_rounded_box_document_round_trips_through_the_tree():
    doc = {"type": "rounded_box", "center": [1, 2, 3], "rotation": [1, 0, 0, 0],
           "euler_deg": [0, 0, 0], "size": [20, 10, 4], "corner": 5}
    leaf = csgfit.tree.tree_from_json3d(doc)
    assert (leaf.type, leaf.size, leaf.corner, leaf.sides) == ("rounded_box", (20, 10, 4), 5, None)
    assert leaf.to_dict() == doc
    assert str(leaf) == "rounded_box(center=(1, 2, 3), size=(20, 10, 4), corner=5)"


def quaternion_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_explicit_voxel_size_is_fitted_in_the_parts_frame_and_refined():
    # A 20 x 10 x 5 box turned 20 degrees about x, then 30 about z, and moved.
    v, t = cube_mesh((-10, -5, -2.5), (10, 5, 2.5))
    a, b = np.radians(30), np.radians(20)
    turn = (np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
            @ np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]]))
    r = csgfit.fit_mesh((v @ turn.T + [3, 4, 5], t), voxel_size=0.5, time=20, seed=1,
                        threads=2)
    assert r.voxel_size == 0.5 and r.stats.primitives == 1 and r.tree.type == "box"
    assert r.stats.iou >= 0.999
    assert r.volume() == pytest.approx(1000, rel=0.01)
    # Turned like the input: each of the box's axes is one of the input's, with its length.
    axes = quaternion_matrix(r.tree.rotation)
    for n, length in enumerate(r.tree.size):
        match = np.abs(turn.T @ axes[:, n])
        assert match.max() == pytest.approx(1, abs=1e-6)
        assert length == pytest.approx((20, 10, 5)[int(match.argmax())], abs=1e-3)
    assert r.tree.center == pytest.approx((3, 4, 5), abs=1e-3)
    # The grid the stats were measured on is the part's frame, as `csgfit mesh` writes it.
    frame = quaternion_matrix(r.document["grid"]["frame"])
    assert np.abs(frame.T @ axes).max(axis=1) == pytest.approx([1, 1, 1], abs=1e-6)


def test_a_primitive_list_without_boxes_is_one_line_of_input_error(tmp_path):
    v, t = cube_mesh((0, 0, 0), (10, 6, 4))
    stl = tmp_path / "block.stl"
    write_stl(stl, v, t)
    npy = tmp_path / "ball.npy"
    np.save(npy, ball())
    for call in (lambda: csgfit.fit_voxels(ball(), primitives=["sphere"]),
                 lambda: csgfit.fit_mesh((v, t), primitives="sphere,cylinder"),
                 lambda: csgfit.fit_mesh(str(stl), primitives=["sphere"]),
                 lambda: csgfit.fit_mesh(str(npy), primitives=["ellipsoid"])):
        with pytest.raises(csgfit.InputError) as info:
            call()
        assert str(info.value) == "the 3D fit needs boxes among the primitives"


def test_2d_and_3d_results_are_the_same_kind_of_object():
    r2 = csgfit.fit_image(np.pad(np.ones((20, 30), bool), 4), time=2, seed=1, threads=2)
    r3 = csgfit.fit_voxels(np.pad(np.ones((12, 8, 6), bool), 2), time=10, seed=1, threads=2)
    for r, leaf in ((r2, csgfit.Primitive), (r3, csgfit.Primitive3D)):
        assert isinstance(r, csgfit.Result)
        assert isinstance(r.tree, leaf) and r.tree.type in ("rectangle", "box")
        assert r.tree.count() == r.stats.primitives == 1 and list(r.tree.walk()) == [r.tree]
        assert r.stats.iou == 1.0 and np.array_equal(r.raster(), r.target())
        assert json.loads(r.to_json())["tree"] == r.tree.to_dict()
        assert repr(r).startswith(type(r).__name__ + "(primitives=1, iou=1.0000")
    assert r3.tree.size == pytest.approx((12, 8, 6)) and r2.tree.w == pytest.approx(30)


def test_find_sweeps_reads_a_tree_as_the_document_does():
    plate = {"op": "difference", "children": [
        {"type": "box", "center": [16, 16, 10], "size": [26, 18, 4]},
        {"type": "cylinder", "center": [8, 11, 10], "r": 2.5, "h": 8},
        {"type": "cylinder", "center": [24, 11, 10], "r": 2.5, "h": 8, "sides": 6}]}
    sweeps = csgfit.find_sweeps(plate)
    assert len(sweeps) == 1
    assert (sweeps[0]["node"], sweeps[0]["kind"], sweeps[0]["height"]) == (0, "linear_extrude", 4)
    assert sweeps[0]["center"] == [0, 0, 8]
    assert [s["type"] for s in sweeps[0]["sections"]] == ["rectangle", "circle", "circle"]
    assert sweeps[0]["sections"][2]["sides"] == 6
    # The same from the tree's objects; a lone primitive or a tree of no sweep has none.
    assert csgfit.find_sweeps(csgfit.Node("difference", [
        csgfit.Primitive3D.from_dict(c) for c in plate["children"]])) == sweeps
    assert csgfit.find_sweeps(plate["children"][0]) == []
    plate["children"][1]["h"] = 2  # a blind hole
    assert csgfit.find_sweeps(plate) == []


def test_a_fitted_block_with_a_bore_is_written_as_an_extrusion():
    # The block of PYTHON.md's example: its bore goes through it.
    i, j, k = np.mgrid[0:42, 0:32, 0:22] + 0.5
    block = (i > 1) & (i < 41) & (j > 1) & (j < 31) & (k > 1) & (k < 21)
    hole = (i - 28) ** 2 + (j - 16) ** 2 < 6 ** 2
    r = csgfit.fit_voxels(block & ~hole, origin=(-1, -1, -1), voxel_size=1.0, time=20, seed=1)
    assert r.stats.primitives == 2
    assert r.document["sweeps"] == csgfit.find_sweeps(r.tree)
    assert r.document["sweeps"][0]["kind"] == "linear_extrude"
    assert "linear_extrude(height = extrude_1_h)" in r.to_scad()
