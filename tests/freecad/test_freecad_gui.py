"""GUI tests of the CSG Fit workbench: FreeCAD under xvfb-run runs gui_macro.py, which drives
"Image to CSG" (on a benchmark bitmap), "Mesh to CSG" (on a mesh object made from a fixture
STL) or "Range image to CSG" (on seed 002's object_b range image) through the task panels' own
code and reports back.

The workbench is installed with scripts/install_workbench.sh into a throw-away HOME, so the
tests also check that FreeCAD finds it where the installer puts it. Screenshots go to the test's
temporary folder, or to docs/img/ with CSGFIT_UPDATE_SCREENSHOTS=1.
"""

import json
import os
import shutil
import subprocess

import pytest

import fchelpers as H

IMAGE = os.path.join(H.BENCH, "glyph_P.png")
PARAMETRIC = {"Part::Box", "Part::Cylinder", "Part::Ellipse", "Part::Extrusion", "Part::Wedge",
              "Part::Sphere", "Part::Cone", "Part::Ellipsoid", "Part::Torus",
              "Part::MultiFuse", "Part::MultiCommon", "Part::Cut",
              # A sweep's profile (sweep_objects.py)
              "Part::Plane", "Part::Circle", "Part::Face", "Part::Revolution"}


def run_macro(tmp_path, scenario, **env_extra):
    """Installs the workbench into a fresh HOME, runs gui_macro.py's scenario in FreeCAD under
    Xvfb; returns (report dict, screenshot folder)."""
    for tool in ("xvfb-run", "freecad"):
        if not shutil.which(tool):
            pytest.skip(f"{tool} not installed")
    if not os.path.exists(os.path.join(H.BUILD, "python", "csgfit", "__init__.py")):
        pytest.skip(f"csgfit module not built in {H.BUILD}/python")
    env = H.installed_home(tmp_path)
    shots = (os.path.join(H.REPO, "docs", "img") if os.environ.get("CSGFIT_UPDATE_SCREENSHOTS")
             else str(tmp_path))
    os.makedirs(shots, exist_ok=True)
    report_path = tmp_path / "report.json"
    env.update(CSGFIT_GUI_REPORT=str(report_path), CSGFIT_GUI_SHOTS=shots,
               CSGFIT_GUI_SCENARIO=scenario, **env_extra)
    proc = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1600x1100x24", "freecad",
                           os.path.join(os.path.dirname(__file__), "gui_macro.py")],
                          env=env, capture_output=True, text=True, timeout=300)
    assert report_path.exists(), f"FreeCAD did not run the macro:\n{proc.stdout}\n{proc.stderr}"
    r = json.loads(report_path.read_text())
    assert r["ok"], r.get("error")
    assert r["workbench"] == "CSG Fit"
    return r, shots


def test_image_to_csg_through_the_task_panel(tmp_path):
    if not os.path.exists(IMAGE):
        pytest.skip(f"benchmark {IMAGE} not present")
    r, shots = run_macro(tmp_path, "image", CSGFIT_GUI_IMAGE=IMAGE)
    assert "missing.png" in r["bad_file_status"]  # the error shows in the panel
    assert r["cancel_seconds"] < 1.0 and r["cancel_stop_reason"] == "cancelled"
    assert r["preview"] and r["iou"] >= 0.95
    assert r["tree_choices"][0].startswith("Best:") and len(r["tree_choices"]) >= 2
    assert r["accepted"] and r["dialog_closed"]
    assert r["groups"] == ["glyph_P"]
    assert r["problems"] == [] and r["root_valid"] and r["root_volume"] > 0
    assert set(r["types"]) <= PARAMETRIC
    assert r["scad_bytes"] > 100
    for name in ("freecad_image_to_csg.png", "freecad_result_tree.png"):
        assert os.path.getsize(os.path.join(shots, name)) > 10000


def test_mesh_to_csg_through_the_task_panel(tmp_path):
    try:
        import FreeCAD  # noqa: F401  (the fixture is written with FreeCAD's Part and Mesh)
    except ImportError as e:
        pytest.skip(f"FreeCAD Python API not available ({e})")
    stl = tmp_path / "block_with_hole.stl"
    mesh_volume = H.make_fixture(stl)
    r, shots = run_macro(tmp_path, "mesh", CSGFIT_GUI_MESH=str(stl))
    assert r["panel_mesh"] == "block_with_hole"  # the selected mesh object is the input
    assert r["cancel_seconds"] < 1.0 and r["cancel_stop_reason"] == "cancelled"
    assert r["preview"] and r["overlay"]  # voxel slice in the panel, the tree in the 3D view
    assert r["iou"] >= 0.97
    assert r["accepted"] and r["dialog_closed"] and not r["overlay_after_accept"]
    assert r["mesh_hidden"]
    # The mesh is drawn as wireframe under the overlaid tree, and restored afterwards.
    assert r["mesh_mode_preview"] == "Wireframe" and r["mesh_mode_after"] != "Wireframe"
    assert r["groups"] == ["block_with_hole CSG"]
    assert r["problems"] == [] and r["root_valid"]
    # The block with its bore through it is a square minus a circle, extruded.
    assert set(r["types"]) <= PARAMETRIC and "Part::Extrusion" in r["types"]
    assert r["mesh_volume"] == pytest.approx(mesh_volume, rel=1e-5)
    assert r["root_volume"] == pytest.approx(mesh_volume, rel=0.015)
    assert r["root_volume"] == pytest.approx(r["fit_volume"], rel=0.01)
    assert "missing.stl" in r["bad_file_status"]
    assert r["scad_bytes"] > 100
    for name in ("freecad_mesh_to_csg.png", "freecad_mesh_result_tree.png"):
        assert os.path.getsize(os.path.join(shots, name)) > 10000


def test_range_to_csg_through_the_task_panel(tmp_path):
    rng = os.path.join(os.path.dirname(H.BENCH), "range", "object_b_ortho.png")
    if not os.path.exists(rng):
        pytest.skip(f"benchmark {rng} not present")
    with open(os.path.splitext(rng)[0] + ".json") as f:
        sidecar = json.load(f)
    r, shots = run_macro(tmp_path, "range", CSGFIT_GUI_RANGE=rng)
    assert "missing.png" in r["bad_file_status"]
    # The sidecar fills the sensor fields; untouched, they are not passed as overrides.
    assert r["projection"] == "orthographic"
    assert r["pixel_size"] == pytest.approx(sidecar["pixel_size"], rel=1e-9)
    assert "object_b_ortho.json" in r["sensor_note"]
    assert r["intrinsics_unedited"] == {} and r["intrinsics_edited"] == ["depth_unit"]
    assert r["cancel_stop_reason"] == "cancelled" and r["cancel_seconds"] < 5.0
    assert r["primitives"] == 5 and r["subobjects"] == 2
    assert r["preview"] and r["report_text"].startswith("There are 2 subobjects:")
    assert r["accepted"] and r["dialog_closed"]
    assert r["groups"] == ["object_b_ortho"]
    assert r["problems"] == [] and r["root_valid"] and r["root_volume"] > 0
    assert set(r["types"]) <= PARAMETRIC and "Part::Cut" in r["types"]
    assert r["scad_bytes"] > 100
    for name in ("freecad_range_to_csg.png", "freecad_range_result_tree.png"):
        assert os.path.getsize(os.path.join(shots, name)) > 10000
