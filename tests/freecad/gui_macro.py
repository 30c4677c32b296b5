# GUI test macro, run by test_freecad_gui.py as `xvfb-run -a freecad gui_macro.py`.
# Drives the CSG Fit workbench through its own code: activates it, then runs the scenario
# $CSGFIT_GUI_SCENARIO: "image" (default) runs "Image to CSG" on the bitmap $CSGFIT_GUI_IMAGE,
# "mesh" runs "Mesh to CSG" on the mesh object made from $CSGFIT_GUI_MESH, "range" runs "Range
# image to CSG" on the range image $CSGFIT_GUI_RANGE, all through the task panel (bad input,
# cancel, fit, preview, accept); it checks the tree, exports OpenSCAD, saves screenshots, writes
# a JSON report to $CSGFIT_GUI_REPORT and exits.
import json
import os
import sys
import time
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from csgfit_freecad.qt import QtCore, QtWidgets

report = {"ok": False, "steps": []}
REPORT = os.environ["CSGFIT_GUI_REPORT"]
SCENARIO = os.environ.get("CSGFIT_GUI_SCENARIO", "image")
SHOTS = os.environ.get("CSGFIT_GUI_SHOTS", os.path.dirname(REPORT))


def step(name, **info):
    report["steps"].append(dict(name=name, **info))


def pump(seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        QtWidgets.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 50)
        time.sleep(0.01)


def wait_fit(panel, limit):
    t0 = time.monotonic()
    while panel.is_running() or panel.timer.isActive():
        QtWidgets.QApplication.processEvents(QtCore.QEventLoop.AllEvents, 50)
        time.sleep(0.01)
        if time.monotonic() - t0 > limit:
            raise RuntimeError("fit did not finish")
    return time.monotonic() - t0


def cancel_a_long_fit(panel, after):
    """Starts the panel's fit, presses Cancel fit `after` seconds later and reports how long
    the fit took to stop and why it stopped."""
    panel.start_fit()
    pump(after)
    t0 = time.monotonic()
    panel.cancel_fit()
    wait_fit(panel, 10)
    report["cancel_seconds"] = time.monotonic() - t0
    report["cancel_stop_reason"] = panel.result.stats.stop_reason if panel.result else None


def shot(name):
    """Screenshot of the main window. QWidget.grab() leaves the OpenGL 3D view blank under
    Xvfb, so the view is rendered off-screen by Coin and painted into its place."""
    from csgfit_freecad.qt import QtGui

    mw = Gui.getMainWindow()
    path = os.path.join(SHOTS, name)
    image = mw.grab().toImage()
    view = Gui.ActiveDocument.ActiveView if Gui.ActiveDocument else None
    gl = None
    for w in mw.findChildren(QtWidgets.QWidget):
        if w.inherits("QGLWidget") or w.inherits("QOpenGLWidget"):
            if w.isVisible() and w.width() > 100:
                gl = w
    if view is not None and gl is not None:
        tmp = path + ".view.png"
        view.saveImage(tmp, gl.width(), gl.height(), "Current")
        painter = QtGui.QPainter(image)
        painter.drawImage(gl.mapTo(mw, QtCore.QPoint(0, 0)), QtGui.QImage(tmp))
        painter.end()
        os.unlink(tmp)
    image.save(path)
    step("screenshot", path=path)


def check_built(doc, builder):
    """Report on the built group (the one csgfit group of doc)."""
    groups = builder.find_groups(doc)
    report["groups"] = [g.Label for g in groups]
    group = groups[0]
    report["problems"] = builder.check_tree(doc, group)
    report["types"] = sorted({o.TypeId for o in builder.tree_objects(group)})
    report["root_valid"] = group.CsgFitRoot.Shape.isValid()
    report["root_volume"] = group.CsgFitRoot.Shape.Volume
    report["dialog_closed"] = not Gui.Control.activeDialog()
    return group


def show_tree(group, builder, prefer):
    """Expand the group and the root in the tree view and select a primitive of type `prefer`
    so that the property editor shows its dimensions."""
    mw = Gui.getMainWindow()
    tree = mw.findChild(QtWidgets.QTreeWidget)
    if tree is not None:
        for label in (group.Label, group.CsgFitRoot.Label):
            for item in tree.findItems(label, QtCore.Qt.MatchExactly | QtCore.Qt.MatchRecursive):
                item.setExpanded(True)
    obj = next((o for o in builder.tree_objects(group) if o.TypeId == prefer), None)
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(obj or group.CsgFitRoot)
    Gui.ActiveDocument.ActiveView.viewIsometric()
    Gui.SendMsgToActiveView("ViewFit")
    pump(0.5)


def main():
    mw = Gui.getMainWindow()
    mw.resize(1400, 1000)
    mw.showNormal()
    dock = mw.findChild(QtWidgets.QDockWidget, "Combo View")
    if dock is not None:
        mw.resizeDocks([dock], [470], QtCore.Qt.Horizontal)
    Gui.activateWorkbench("CSGFitWorkbench")
    report["workbench"] = Gui.activeWorkbench().MenuText
    {"image": image_scenario, "mesh": mesh_scenario, "range": range_scenario}[SCENARIO]()


def image_scenario():
    from csgfit_freecad import builder, commands

    IMAGE = os.environ["CSGFIT_GUI_IMAGE"]
    doc = App.newDocument("ImageToCSG")
    Gui.runCommand(commands.IMAGE_TO_CSG)
    pump(0.5)
    panel = commands.active_panel
    assert panel is not None, "the command did not open the panel"
    step("panel opened")

    # A bad file: the error shows in the panel.
    panel.set_file("/nonexistent/missing.png")
    report["bad_file_status"] = panel.status.text()

    panel.set_file(IMAGE)
    panel.pixel_size.setValue(0.5)
    panel.alternatives.setValue(2)

    # Cancel: a long fit stops promptly.
    panel.time.setValue(30)
    panel.quality.setCurrentText("best")
    cancel_a_long_fit(panel, 0.3)

    # The real fit.
    panel.time.setValue(3)
    panel.quality.setCurrentText("default")
    panel.start_fit()
    report["fit_seconds"] = wait_fit(panel, 60)
    report["status"] = panel.status.text()
    report["tree_choices"] = [panel.tree_choice.itemText(i)
                              for i in range(panel.tree_choice.count())]
    report["preview"] = not panel.preview.pixmap().isNull()
    report["iou"] = panel.result.stats.iou
    pump(0.3)
    shot("freecad_image_to_csg.png")

    accepted = panel.accept()
    pump(0.5)
    report["accepted"] = bool(accepted)
    group = check_built(doc, builder)
    show_tree(group, builder, "Part::Box")
    shot("freecad_result_tree.png")

    # Export OpenSCAD through the command's code.
    scad = os.path.join(os.path.dirname(REPORT), "gui_export.scad")
    commands.export_scad(group, scad)
    report["scad_bytes"] = os.path.getsize(scad)
    report["ok"] = True


def mesh_scenario():
    import Mesh
    from csgfit_freecad import builder, commands

    path = os.environ["CSGFIT_GUI_MESH"]
    doc = App.newDocument("MeshToCSG")
    mesh = doc.addObject("Mesh::Feature", "block_with_hole")
    mesh.Mesh = Mesh.Mesh(path)
    doc.recompute()
    Gui.SendMsgToActiveView("ViewFit")
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(mesh)
    Gui.runCommand(commands.MESH_TO_CSG)
    pump(0.5)
    panel = commands.active_panel
    assert panel is not None and type(panel).__name__ == "MeshToCsgPanel", \
        "the command did not open the Mesh to CSG panel"
    report["panel_mesh"] = panel.mesh_object.Label if panel.mesh_object else None
    step("panel opened")

    # Cancel: a long fit stops promptly and keeps the best tree so far. Built from its faces
    # this block is done in a moment, so the search alone is what gets cancelled.
    panel.time.setValue(60)
    panel.construct.setChecked(False)
    cancel_a_long_fit(panel, 0.5)
    panel.construct.setChecked(True)

    # The real fit (the faces explain this part: it is built, not searched).
    panel.time.setValue(30)
    panel.quality.setCurrentIndex(0)  # 64 voxels along the longest side: converges in seconds
    panel.seed.setValue(1)
    panel.start_fit()
    report["fit_seconds"] = wait_fit(panel, 60)
    report["status"] = panel.status.text()
    report["preview"] = not panel.preview.pixmap().isNull()
    report["overlay"] = panel.overlay.node is not None
    report["mesh_mode_preview"] = mesh.ViewObject.DisplayMode
    report["iou"] = panel.result.stats.iou
    report["primitives"] = panel.result.stats.primitives
    report["fit_volume"] = panel.result.volume()
    pump(0.3)
    shot("freecad_mesh_to_csg.png")

    accepted = panel.accept()
    pump(0.5)
    report["accepted"] = bool(accepted)
    report["overlay_after_accept"] = panel.overlay.node is not None
    report["mesh_hidden"] = not mesh.ViewObject.Visibility
    report["mesh_mode_after"] = mesh.ViewObject.DisplayMode
    report["mesh_volume"] = mesh.Mesh.Volume
    group = check_built(doc, builder)
    show_tree(group, builder, "Part::Cylinder")
    shot("freecad_mesh_result_tree.png")

    # A file that is not a mesh: the panel says so in its status line.
    Gui.Control.closeDialog()
    from csgfit_freecad.mesh_panel import MeshToCsgPanel

    bad = MeshToCsgPanel(path="/nonexistent/missing.stl")
    report["bad_file_status"] = bad.status.text()

    scad = os.path.join(os.path.dirname(REPORT), "gui_export_mesh.scad")
    commands.export_scad(group, scad)
    report["scad_bytes"] = os.path.getsize(scad)
    report["ok"] = True


def range_scenario():
    from csgfit_freecad import builder, commands

    path = os.environ["CSGFIT_GUI_RANGE"]
    doc = App.newDocument("RangeToCSG")
    Gui.runCommand(commands.RANGE_TO_CSG)
    pump(0.5)
    panel = commands.active_panel
    assert panel is not None and type(panel).__name__ == "RangeToCsgPanel", \
        "the command did not open the Range image to CSG panel"
    step("panel opened")

    panel.set_file("/nonexistent/missing.png")
    report["bad_file_status"] = panel.status.text()
    panel.set_file(path)
    report["projection"] = panel.projection.currentText()
    report["pixel_size"] = panel.sensor["pixel_size"].value()
    report["sensor_note"] = panel.sensor_note.text()
    report["intrinsics_unedited"] = panel.intrinsics()
    # A field typed over the sidecar is passed as an override, and only that one.
    panel.sensor["depth_unit"].setValue(panel.sensor["depth_unit"].value() * 2)
    report["intrinsics_edited"] = sorted(panel.intrinsics())
    panel.set_file(path)  # choosing the file again reads the sidecar again

    panel.time.setValue(60)
    cancel_a_long_fit(panel, 0.2)

    panel.time.setValue(20)
    panel.seed.setValue(1)
    panel.start_fit()
    report["fit_seconds"] = wait_fit(panel, 60)
    report["status"] = panel.status.text()
    report["preview"] = not panel.preview.pixmap().isNull()
    report["report_text"] = panel.report_text.toPlainText()
    report["primitives"] = panel.result.stats.primitives
    report["subobjects"] = panel.result.precedence_graph.subobjects
    pump(0.3)
    shot("freecad_range_to_csg.png")

    accepted = panel.accept()
    pump(0.5)
    report["accepted"] = bool(accepted)
    group = check_built(doc, builder)
    show_tree(group, builder, "Part::Cylinder")
    shot("freecad_range_result_tree.png")
    scad = os.path.join(os.path.dirname(REPORT), "gui_export_range.scad")
    commands.export_scad(group, scad)
    report["scad_bytes"] = os.path.getsize(scad)
    report["ok"] = True


try:
    main()
except Exception:
    report["error"] = traceback.format_exc()
finally:
    with open(REPORT, "w") as f:
        json.dump(report, f, indent=1)
    sys.stdout.flush()
    os._exit(0)
