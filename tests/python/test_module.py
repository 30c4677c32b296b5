"""Tests of the csgfit Python module (run with /usr/bin/python3 -m pytest tests/python).

The module is looked up in $CSGFIT_BUILD_DIR/python (default: <repo>/build/python); the tests
are skipped, with the reason, when it has not been built (-DCSGFIT_BUILD_PYTHON=ON).
"""

import json
import os
import shutil
import re
import threading
import time

import numpy as np
import pytest

from built import BENCHMARKS, REPO, csgfit  # noqa: E402
BENCH = os.path.join(BENCHMARKS, "2d")


def rect_minus_circle(w=64, h=48):
    """A plate with a hole: True = shape, row 0 at the top."""
    yy, xx = np.mgrid[0:h, 0:w]
    plate = (xx >= 8) & (xx < w - 8) & (yy >= 6) & (yy < h - 6)
    hole = (xx + 0.5 - w * 0.55) ** 2 + (yy + 0.5 - h / 2) ** 2 <= 9.5 ** 2
    return plate & ~hole


def busy_shape(n=160, seed=7):
    """Many overlapping blobs: a fit that does not converge in a fraction of a second."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n]
    mask = np.zeros((n, n), bool)
    for _ in range(40):
        cx, cy, r = rng.uniform(10, n - 10), rng.uniform(10, n - 10), rng.uniform(3, 14)
        if rng.random() < 0.7:
            mask |= (xx - cx) ** 2 + (yy - cy) ** 2 <= r * r
        else:
            mask &= ~((xx - cx) ** 2 + (yy - cy) ** 2 <= r * r)
    return mask


def iou(a, b):
    a, b = np.asarray(a, bool), np.asarray(b, bool)
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else np.logical_and(a, b).sum() / union


def test_numpy_in_tree_out():
    mask = rect_minus_circle()
    r = csgfit.fit_image(mask, pixel_size=0.5, time=5, threads=2, seed=3)
    raster = r.raster()
    assert raster.shape == mask.shape and raster.dtype == np.bool_
    assert iou(raster, mask) >= 0.97
    assert r.stats.iou == pytest.approx(iou(raster, mask), abs=1e-9)
    assert r.stats.primitives == r.tree.count() >= 2
    assert r.stats.stop_reason in ("converged", "time", "max-trees")
    assert np.array_equal(r.target(), mask)
    assert (r.width, r.height) == (64, 48)
    # Model units: the canvas is 32 x 24 mm; every centre lies on it.
    for node in r.tree.walk():
        if node.op == "primitive":
            assert 0 <= node.cx <= 32 and 0 <= node.cy <= 24, node
            assert node.type in csgfit.PRIMITIVE_TYPES
    assert "difference" in str(r.tree) or "intersection" in str(r.tree)


def test_uint8_grey_dark_is_shape_like_files():
    mask = rect_minus_circle()
    grey = np.where(mask, 20, 235).astype(np.uint8)
    r = csgfit.fit_image(grey, time=3, threads=2, seed=1)
    assert np.array_equal(r.target(), mask)
    assert iou(r.raster(), mask) >= 0.97
    inv = csgfit.fit_image(np.where(mask, 235, 20).astype(np.uint8), invert=True, time=0.5)
    assert np.array_equal(inv.target(), mask)
    assert np.array_equal(csgfit.fit_image(~mask, invert=True, time=0.5).target(), mask)


def test_same_seed_same_tree():
    mask = rect_minus_circle(48, 40)
    runs = [csgfit.fit_image(mask, time=60, threads=1, seed=11, quality="fast")
            for _ in range(2)]
    for r in runs:
        # Bounded by convergence, not the clock, or the comparison would depend on load.
        assert r.stats.stop_reason in ("converged", "max-trees"), r.stats
    assert runs[0].tree == runs[1].tree
    docs = [json.loads(r.to_json()) for r in runs]
    for d in docs:  # everything but the wall time must agree
        d["stats"].pop("seconds")
        for alt in d["alternatives"]:
            alt["stats"].pop("seconds")
    assert docs[0] == docs[1]


def test_cancel_from_another_thread_within_a_second():
    token = csgfit.CancelToken()
    out = {}

    def work():
        out["result"] = csgfit.fit_image(busy_shape(), time=30, quality="best", cancel=token)

    t0 = time.monotonic()
    th = threading.Thread(target=work)
    th.start()
    time.sleep(0.3)
    token.cancel()
    th.join(10)
    elapsed = time.monotonic() - t0
    assert not th.is_alive()
    assert elapsed < 1.5, f"cancel took {elapsed:.2f} s"
    assert out["result"].stats.stop_reason == "cancelled"
    assert token.cancelled
    assert out["result"].tree.count() >= 1  # the best tree so far comes back


def test_gil_is_released_during_the_fit():
    ticks = 0
    done = threading.Event()

    def work():
        csgfit.fit_image(busy_shape(), time=1.0, threads=1)
        done.set()

    th = threading.Thread(target=work)
    th.start()
    time.sleep(0.1)
    t_end = time.monotonic() + 0.4
    while time.monotonic() < t_end:
        ticks += 1
    th.join()
    # A held GIL would leave this thread a few switch intervals at most.
    assert ticks > 10000


def test_progress_callback_reports_and_can_cancel():
    seen = []

    def progress(p):
        seen.append((p.fraction, p.best_primitives, p.seconds))
        return p.seconds < 0.3

    t0 = time.monotonic()
    r = csgfit.fit_image(busy_shape(), time=30, quality="best", progress=progress)
    assert time.monotonic() - t0 < 2.0
    assert seen and all(0.0 <= f <= 1.0 for f, _, _ in seen)
    assert r.stats.stop_reason == "cancelled"


def test_progress_callback_exception_propagates():
    def progress(p):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        csgfit.fit_image(busy_shape(), time=30, progress=progress)


def test_all_background_raises_no_shape_found():
    with pytest.raises(ValueError, match="no shape found"):
        csgfit.fit_image(np.zeros((20, 30), bool))
    with pytest.raises(ValueError, match="no shape found"):
        csgfit.fit_image(np.full((20, 30), 255, np.uint8), threshold=128)


@pytest.mark.parametrize("array, message", [
    (np.zeros((4, 5, 3), np.uint8), "2D array"),
    (np.zeros(7, bool), "2D array"),
    (np.zeros((0, 5), bool), "empty image"),
    (np.ones((5, 5), np.float64), "dtype"),
])
def test_bad_arrays_raise_value_error(array, message):
    with pytest.raises(ValueError, match=message) as info:
        csgfit.fit_image(array)
    assert "\n" not in str(info.value)


def test_missing_and_broken_files_raise_value_error(tmp_path):
    missing = tmp_path / "nope.png"
    with pytest.raises(ValueError, match="nope.png") as info:
        csgfit.fit_image(missing)
    assert isinstance(info.value, csgfit.InputError)
    assert "\n" not in str(info.value)
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"\x89PNG\r\n\x1a\n not really")
    with pytest.raises(ValueError, match="broken.png"):
        csgfit.fit_image(str(broken))


@pytest.mark.parametrize("kwargs, message", [
    ({"quality": "superb"}, "quality"),
    ({"primitives": ["hexagon"]}, "hexagon"),
    ({"time": 0}, "time"),
    ({"threads": -1}, "threads"),
    ({"pixel_size": 0}, "pixel_size"),
    ({"cancel": object()}, "CancelToken"),
])
def test_bad_options_raise_value_error(kwargs, message):
    with pytest.raises(ValueError, match=message):
        csgfit.fit_image(rect_minus_circle(), **kwargs)


def test_primitive_restriction_and_alternatives():
    mask = rect_minus_circle()
    r = csgfit.fit_image(mask, time=2, primitives=["rectangle", "circle"], alternatives=2)
    types = {n.type for n in r.tree.walk() if n.op == "primitive"}
    assert types <= {"rectangle", "circle"}
    assert len(r.alternatives) <= 2
    for alt in r.alternatives:
        assert alt.raster().shape == mask.shape
        assert alt.tree.count() == alt.stats.primitives
        assert alt.tree != r.tree


def test_json_and_scad_outputs_round_trip(tmp_path):
    mask = rect_minus_circle()
    r = csgfit.fit_image(mask, pixel_size=0.25, thickness=3, time=2, seed=2)
    doc = json.loads(r.to_json())
    assert doc["schema"] == "csgfit/1"
    assert doc["canvas"]["pixel_size"] == 0.25 and doc["canvas"]["thickness"] == 3
    assert doc["tree"] == json.loads(json.dumps(r.tree.to_dict()))
    again = csgfit.load_json(r.to_json())
    assert np.array_equal(again.raster(), r.raster())
    assert again.target() is None
    path = tmp_path / "r.json"
    path.write_text(r.to_json())
    assert np.array_equal(csgfit.load_json(str(path)).raster(), r.raster())
    scad = r.to_scad()
    assert "linear_extrude" in scad and "$fn" in scad
    r.thickness = 0
    assert "linear_extrude" not in r.to_scad()
    with pytest.raises(ValueError):
        csgfit.load_json('{"schema": "csgfit/1"}')
    with pytest.raises(csgfit.InputError, match="cannot open .*missing.json") as info:
        csgfit.load_json(tmp_path / "missing.json")
    assert "\n" not in str(info.value)


def test_benchmark_file_matches_load_bitmap():
    path = os.path.join(BENCH, "glyph_P.png")
    if not os.path.exists(path):
        pytest.skip(f"benchmark bitmap {path} not present")
    r = csgfit.fit_image(path, time=2, seed=1)
    assert np.array_equal(r.target(), csgfit.load_bitmap(path))
    assert r.source == "glyph_P.png"
    assert r.stats.iou >= 0.95


def test_docs_example_runs_as_written(tmp_path, monkeypatch):
    doc = os.path.join(REPO, "docs", "PYTHON.md")
    if not os.path.exists(doc):
        pytest.skip("docs/PYTHON.md not written")
    blocks = re.findall(r"```python\n(.*?)```", open(doc, encoding="utf-8").read(), re.S)
    assert blocks, "docs/PYTHON.md has no python example"
    monkeypatch.chdir(tmp_path)
    # The range example reads object_b's view A as a user would have it: beside the script.
    shared = os.path.join(REPO, "..", "shared", "benchmarks")
    for folder, name in (("range", "object_b_ortho.png"), ("range", "object_b_ortho.json"),
                         ("points", "blade_top.xyz")):
        if os.path.exists(os.path.join(shared, folder, name)):
            shutil.copy(os.path.join(shared, folder, name), tmp_path / name)
    for code in blocks:
        needs = [n for n in ("object_b_ortho.png", "blade_top.xyz") if n in code]
        if any(not (tmp_path / n).exists() for n in needs):
            continue  # no benchmarks beside the repository
        exec(compile(code, doc, "exec"), {"__name__": "__docs__"})
