"""The module's answers to hostile arguments (the hardening issue): every bad number, type, array
or text is one short csgfit.InputError line, raised before any work, never a pybind TypeError
with its signature dump and never a silent truncation (run with /usr/bin/python3 -m pytest)."""

import os
import re
import time

import numpy as np
import pytest

from built import REPO, csgfit  # noqa: E402

SQUARE = np.zeros((24, 24), bool)
SQUARE[6:18, 4:20] = True
CUBE_V = np.array([[x, y, z] for x in (0, 8) for y in (0, 8) for z in (0, 8)], float)
CUBE_T = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7),
                   (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def refused(call, *words):
    """Runs call, which must raise InputError with one short line naming every word, at once."""
    start = time.monotonic()
    with pytest.raises(csgfit.InputError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message and len(message) <= 400, message
    assert message.isprintable(), message
    for word in words:
        assert word in message, message
    assert time.monotonic() - start < 5, "refused only after working"
    return message


@pytest.mark.parametrize("kwargs, word", [
    (dict(threads=2 ** 31), "threads"),
    (dict(threads=-1), "threads"),
    (dict(threads=1.5), "threads"),
    (dict(threads="2"), "threads"),
    (dict(seed=-1), "seed"),
    (dict(seed=2 ** 64), "seed"),
    (dict(k=-5), "k"),
    (dict(k=float("nan")), "k"),
    (dict(time=float("nan")), "time"),
    (dict(time=-1), "time"),
    (dict(pixel_size=float("nan")), "pixel_size"),
    (dict(pixel_size=1e300), "pixel_size"),
    (dict(thickness=float("nan")), "thickness"),
    (dict(alternatives=10 ** 30), "alternatives"),
    (dict(threshold=300), "threshold"),
])
def test_image_arguments_are_checked_up_front(kwargs, word):
    refused(lambda: csgfit.fit_image(SQUARE, **{"time": 60, **kwargs}), word)


def test_mesh_and_range_arguments_are_checked_up_front():
    refused(lambda: csgfit.fit_mesh((CUBE_V, CUBE_T), time=60, threads=10 ** 6), "threads")
    refused(lambda: csgfit.fit_mesh((CUBE_V, CUBE_T), time=60, resolution=-3), "resolution")
    refused(lambda: csgfit.fit_mesh((CUBE_V, CUBE_T), time=60, voxel_size=float("inf")),
            "voxel_size")
    refused(lambda: csgfit.fit_range("part.png", fx=float("nan")), "fx")
    refused(lambda: csgfit.fit_points(np.zeros((10, 3)), seed=-1), "seed")


def test_float_triangle_indices_are_not_truncated():
    refused(lambda: csgfit.fit_mesh((CUBE_V, CUBE_T + 0.5), time=60), "integer")
    # Whole numbers stored as floats are the same mesh.
    result = csgfit.fit_mesh((CUBE_V, CUBE_T.astype(float)), time=1, seed=1)
    assert result.stats.iou > 0.99


def test_zero_stride_arrays_are_measured_by_what_they_claim():
    voxels = np.broadcast_to(np.ones(1, bool), (10 ** 5,) * 3)
    message = refused(lambda: csgfit.fit_voxels(voxels, time=60), "memory budget")
    assert "100000 x 100000 x 100000" in message
    image = np.broadcast_to(np.ones(1, bool), (100000, 100000))
    refused(lambda: csgfit.fit_image(image, time=60), "100000 x 100000")
    points = np.broadcast_to(np.ones(3), (10 ** 10, 3))
    refused(lambda: csgfit.fit_points(points, time=60), "memory budget")
    # A small broadcast array is a valid input, fitted as its contiguous copy.
    small = np.broadcast_to(SQUARE[None, :, :12], (12, 24, 12)).transpose(1, 2, 0)
    assert csgfit.fit_voxels(small, time=1).stats.iou > 0.99


def test_load_json_tells_text_from_paths_and_keeps_messages_short():
    refused(lambda: csgfit.load_json("x" * 2_000_000), "JSON")
    refused(lambda: csgfit.load_json("not json\nat all"), "JSON")
    refused(lambda: csgfit.load_json("/no/such/result.json"), "/no/such/result.json")


def test_max_memory_bounds_every_large_allocation():
    refused(lambda: csgfit.set_max_memory("1K"), "max_memory")
    refused(lambda: csgfit.set_max_memory(1.5), "max_memory")
    try:
        csgfit.set_max_memory("16M")
        refused(lambda: csgfit.fit_voxels(np.ones((400, 400, 400), bool), time=60),
                "memory budget")
    finally:
        csgfit.set_max_memory(None)
    assert csgfit.fit_image(SQUARE, time=0.5).stats.iou > 0.99


def test_the_readme_lists_every_rule_as_the_solver_checks_it():
    header = open(os.path.join(REPO, "native/include/csgfit/pipeline/option_limits.h")).read()
    readme = open(os.path.join(REPO, "README.md")).read()
    rows = {line.split("|")[1].strip(): line for line in readme.splitlines()
            if line.startswith("| ") and line.count("|") == 4}
    names = re.findall(r"inline constexpr NumberRule (\w+)\{", header)
    assert len(names) >= 13
    for name in names:
        if name == "memory":  # parsed from text such as 4G; its row says so
            assert "16M .. 1024T" in rows["memory"]
            continue
        why = csgfit._csgfit.rule_violation(name, float("nan"))
        accepted = re.search(r" in (\S+(?: \.\. |, )\S+), not nan$", why).group(1)
        assert name in rows, f"README's Limits table has no row for {name}"
        assert accepted in rows[name], f"{name}: README says {rows[name]!r}, solver {accepted}"
