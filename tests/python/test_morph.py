"""csgfit.morph and `csgfit morph`: two trees of one structure, each matching its own shape;
the .scad's `morph` parameter gives A at 0 and B at 1 in OpenSCAD's rendering; frames, GIF and
bad input refused in one line with no output file."""

import json
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
import scad_raster  # noqa: E402

H, W = 64, 80


def disc_with_bar():
    y, x = np.mgrid[0:H, 0:W] + 0.5
    return ((x - 40) ** 2 + (y - 32) ** 2 <= 18 ** 2) | ((abs(x - 40) <= 30) & (abs(y - 32) <= 4))


def frame_shape():
    y, x = np.mgrid[0:H, 0:W] + 0.5
    outer = (abs(x - 40) <= 26) & (abs(y - 32) <= 20)
    inner = (abs(x - 40) <= 14) & (abs(y - 32) <= 8)
    return outer & ~inner


def iou(a, b):
    return (a & b).sum() / max(1, (a | b).sum())


def shape_of(tree):
    """Operators and primitive types in pre-order: what must agree between the two trees."""
    return [getattr(n, "op", None) or n.type for n in tree.walk()]


@pytest.fixture(scope="module")
def pair():
    return csgfit.morph(disc_with_bar(), frame_shape(), time=60, threads=1, seed=3)


def test_both_trees_share_one_structure_and_match_their_shapes(pair):
    assert shape_of(pair.tree_a) == shape_of(pair.tree_b)
    assert len(pair.leaves) == pair.tree_a.count()
    assert iou(pair.frame(0), disc_with_bar()) > 0.93
    assert iou(pair.frame(1), frame_shape()) > 0.95
    assert pair.stats_a.iou == pytest.approx(iou(pair.frame(0), disc_with_bar()), abs=1e-9)
    assert pair.frame(0.5).any()


def test_openscad_renders_a_at_0_and_b_at_1(pair, tmp_path):
    if scad_raster.find_openscad() is None:
        pytest.skip("openscad is not installed")
    path = tmp_path / "m.scad"
    path.write_text(pair.to_scad())
    for t, solver in ((0, pair.frame(0)), (1, pair.frame(1)), (0.5, pair.frame(0.5))):
        mask = scad_raster.rasterize_scad(str(path), W, H, 1.0, defines={"morph": t})
        assert scad_raster.agreement(mask, solver) > 0.99, t


def test_json_holds_both_trees(pair, tmp_path):
    doc = json.loads(pair.to_json())
    assert doc["dimension"] == 2 and "tree_b" in doc["morph"]
    assert len(doc["morph"]["leaves"]) == pair.tree_a.count()
    assert pair.save(tmp_path / "m.json").endswith("m.json")


def test_a_saved_morph_loads_back_and_exports_the_same_scad(pair, tmp_path):
    path = pair.save(tmp_path / "m.json")
    back = csgfit.load_json(path)
    assert isinstance(back, csgfit.MorphResult)
    assert back.to_scad() == pair.to_scad()
    assert (back.frame(0.5) == pair.frame(0.5)).all()
    out = run("export", path, "-o", tmp_path / "m.scad")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "m.scad").read_text() == pair.to_scad()
    back.thickness = 3.0  # as FreeCAD's Export OpenSCAD sets it from the group's cell
    assert "linear_extrude(height = thickness)" in back.to_scad()
    out = run("export", path, "-o", tmp_path / "m.step")
    assert out.returncode == 2 and "two solids" in out.stderr


def test_bad_input_is_refused():
    with pytest.raises(csgfit.InputError, match="differ in size"):
        csgfit.morph(disc_with_bar(), np.ones((10, 10), bool), time=1)
    with pytest.raises(csgfit.InputError, match="no shape"):
        csgfit.morph(disc_with_bar(), np.zeros((H, W), bool), time=1)
    with pytest.raises(csgfit.InputError, match="preset"):
        csgfit.morph(disc_with_bar(), frame_shape(), preset="fastest")
    with pytest.raises(csgfit.InputError, match="rotation"):
        csgfit.morph(disc_with_bar(), frame_shape(), rotate="left")
    with pytest.raises(csgfit.InputError, match="one of each"):
        csgfit.morph("a.png", "b.stl")


def write_png(path, mask):
    from PIL import Image
    Image.fromarray(np.where(mask, 0, 255).astype(np.uint8)).save(path)


def run(*args):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)


def test_cli_writes_a_gif_and_frames(tmp_path):
    from PIL import Image
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    write_png(a, disc_with_bar())
    write_png(b, frame_shape())
    out = run("morph", a, b, "-o", tmp_path / "m.gif", "--time", 5, "--frames", 6,
              "--frames-dir", tmp_path / "frames", "-q")
    assert out.returncode == 0, out.stderr
    gif = Image.open(tmp_path / "m.gif")
    assert gif.n_frames == 6
    first = np.array(gif.convert("L")) < 128
    assert iou(first[::2, ::2], np.array(Image.open(tmp_path / "frames" / "frame_000.png")) < 128) == 1.0
    assert len(os.listdir(tmp_path / "frames")) == 6


@pytest.mark.parametrize("case", ["sizes", "empty", "mixed", "missing", "format", "option"])
def test_cli_bad_input_exits_2_without_output(tmp_path, case):
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    write_png(a, disc_with_bar())
    write_png(b, frame_shape())
    out_file = tmp_path / "m.scad"
    args = {"sizes": (a, tmp_path / "small.png"), "empty": (a, tmp_path / "blank.png"),
            "mixed": (a, tmp_path / "x.stl"), "missing": (a, tmp_path / "none.png"),
            "format": (a, b), "option": (a, b)}[case]
    write_png(tmp_path / "small.png", np.ones((8, 8), bool) & (np.arange(8) < 4))
    write_png(tmp_path / "blank.png", np.zeros((H, W), bool))
    (tmp_path / "x.stl").write_text("solid x\nendsolid x\n")
    extra = {"format": ["-o", tmp_path / "m.step"], "option": ["-o", out_file, "--frames", "1"]}
    out = run("morph", *args, *extra.get(case, ["-o", out_file]), "--time", 1)
    assert out.returncode == 2, (case, out.stderr)
    assert len(out.stderr.strip().splitlines()) == 1, out.stderr
    assert not out_file.exists() and not (tmp_path / "m.step").exists()
