"""GUI commands of the CSG Fit workbench: "Image to CSG", "Mesh to CSG", "Range image to CSG",
"Morph two images", "Optimize CSG tree" and "Export OpenSCAD"."""

import os

import FreeCAD as App
import FreeCADGui as Gui
from .qt import QtWidgets

from . import builder, icon, import_csgfit

IMAGE_TO_CSG = "CSGFit_ImageToCSG"
MESH_TO_CSG = "CSGFit_MeshToCSG"
RANGE_TO_CSG = "CSGFit_RangeToCSG"
MORPH_IMAGES = "CSGFit_MorphImages"
EXPORT_SCAD = "CSGFit_ExportOpenSCAD"
OPTIMIZE_TREE = "CSGFit_OptimizeTree"
COMMANDS = [IMAGE_TO_CSG, MESH_TO_CSG, RANGE_TO_CSG, MORPH_IMAGES, OPTIMIZE_TREE, EXPORT_SCAD]
#: The last fit panel opened (scripts and the GUI test drive it).
active_panel = None


def _message(title, text):
    QtWidgets.QMessageBox.warning(Gui.getMainWindow(), title, text)


class ImageToCsgCommand:
    """Opens the Image to CSG task panel."""

    def GetResources(self):
        return {"Pixmap": icon("csgfit_image_to_csg"),
                "MenuText": "Image to CSG",
                "ToolTip": "Fit a parametric CSG tree of primitives to a bitmap"}

    def IsActive(self):
        return not Gui.Control.activeDialog()

    def Activated(self):
        global active_panel
        from .image_panel import ImageToCsgPanel
        active_panel = ImageToCsgPanel()
        Gui.Control.showDialog(active_panel)


def selected_mesh():
    """The first selected mesh object (Mesh::Feature), or None."""
    from .mesh_input import is_mesh_object

    return next((o for o in Gui.Selection.getSelection() if is_mesh_object(o)), None)


class MeshToCsgCommand:
    """Opens the Mesh to CSG task panel on the selected mesh, or asks for a file."""

    def GetResources(self):
        return {"Pixmap": icon("csgfit_mesh_to_csg"),
                "MenuText": "Mesh to CSG",
                "ToolTip": "Fit a parametric CSG tree of 3D primitives to the selected mesh "
                           "(or to a mesh or voxel file)"}

    def IsActive(self):
        return not Gui.Control.activeDialog()

    def Activated(self):
        global active_panel
        from .mesh_input import FILE_FILTER
        from .mesh_panel import MeshToCsgPanel

        mesh = selected_mesh()
        path = None
        if mesh is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(
                Gui.getMainWindow(), "Mesh to CSG: mesh or voxels to fit", "", FILE_FILTER)
            if not path:
                return
        active_panel = MeshToCsgPanel(mesh_object=mesh, path=path)
        Gui.Control.showDialog(active_panel)


class RangeToCsgCommand:
    """Opens the Range image to CSG task panel (the files are chosen in it)."""

    def GetResources(self):
        return {"Pixmap": icon("csgfit_range_to_csg"),
                "MenuText": "Range image to CSG",
                "ToolTip": "Fit a parametric CSG tree (blocks and cylinders in machining order) "
                           "to range images or point clouds of one part"}

    def IsActive(self):
        return not Gui.Control.activeDialog()

    def Activated(self):
        global active_panel
        from .range_panel import RangeToCsgPanel

        active_panel = RangeToCsgPanel()
        Gui.Control.showDialog(active_panel)


class MorphImagesCommand:
    """Opens the Morph two images task panel (both bitmaps are chosen in it)."""

    def GetResources(self):
        return {"Pixmap": icon("csgfit_morph_images"),
                "MenuText": "Morph two images",
                "ToolTip": "Fit two bitmaps with CSG trees of one structure and build one "
                           "parametric tree whose 'morph' cell (0 to 1) moves from one to the "
                           "other"}

    def IsActive(self):
        return not Gui.Control.activeDialog()

    def Activated(self):
        global active_panel
        from .morph_panel import MorphPanel

        active_panel = MorphPanel()
        Gui.Control.showDialog(active_panel)


def selected_group():
    """The csgfit group of the selection (the group itself or any object inside it)."""
    for obj in Gui.Selection.getSelection():
        if hasattr(obj, "CsgFitJson"):
            return obj
        for parent in obj.InListRecursive:
            if hasattr(parent, "CsgFitJson"):
                return parent
    doc = App.ActiveDocument
    groups = builder.find_groups(doc) if doc else []
    return groups[0] if len(groups) == 1 else None


def export_scad(group, path):
    """Writes the tree stored on a csgfit group as .scad, with the group's current thickness
    (the parameter sheet's cell) and the tree the group shows."""
    if getattr(group, "CsgFitDimension", 2) == 3:
        scad = getattr(group, "CsgFitScad", "")
        if not scad:
            raise ValueError("this 3D result carries no OpenSCAD text (write it with the csgfit "
                             "command's -o X.scad: csgfit mesh, range or points)")
        tmp = path + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(scad)
        os.replace(tmp, path)
        return path
    csgfit = import_csgfit()
    result = csgfit.load_json(group.CsgFitJson)
    sheet = next((o for o in group.Group if o.TypeId == "Spreadsheet::Sheet"), None)
    if sheet is not None:
        result.thickness = float(sheet.get("thickness"))
    index = getattr(group, "CsgFitAlternative", -1)
    text = result.to_scad() if index < 0 else result.alternatives[index].to_scad()
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)
    return path


class ExportScadCommand:
    """Writes the selected CSG Fit result as an OpenSCAD file."""

    def GetResources(self):
        return {"Pixmap": icon("csgfit_export_scad"),
                "MenuText": "Export OpenSCAD",
                "ToolTip": "Write the selected CSG Fit result as an OpenSCAD (.scad) file"}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        group = selected_group()
        if group is None:
            _message("Export OpenSCAD", "Select a CSG Fit result (its group or any object in it).")
            return
        default = os.path.join(os.path.expanduser("~"), group.Label + ".scad")
        path, _ = QtWidgets.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Export OpenSCAD",
                                                        default, "OpenSCAD (*.scad)")
        if not path:
            return
        try:
            export_scad(group, path)
        except Exception as e:
            _message("Export OpenSCAD", f"Could not write {path}: {e}")
            return
        App.Console.PrintMessage(f"CSG Fit: wrote {path}\n")


class OptimizeTreeCommand:
    """Builds the selected boolean tree's optimised twin beside it (seed 001's optimiser)."""

    METHODS = ["auto", "espresso", "qmc", "setcover", "ga"]

    def GetResources(self):
        return {"Pixmap": icon("csgfit_optimize_tree"),
                "MenuText": "Optimize CSG tree",
                "ToolTip": "Build a smaller parametric tree of the same solid beside the selected "
                           "Part boolean tree (the original is hidden, one undo step)"}

    def IsActive(self):
        from .optimize_tree import is_boolean_tree

        selection = Gui.Selection.getSelection()
        return App.ActiveDocument is not None and bool(selection) and is_boolean_tree(selection[0])

    def Activated(self):
        from .optimize_tree import optimize_object

        obj = Gui.Selection.getSelection()[0]
        method, ok = QtWidgets.QInputDialog.getItem(
            Gui.getMainWindow(), "Optimize CSG tree", "Remaining-solid optimiser:", self.METHODS, 0, False)
        if not ok:
            return
        try:
            root, result = optimize_object(obj, method=method)
        except Exception as e:
            _message("Optimize CSG tree", f"Could not optimise {obj.Label}: {e}")
            return
        front = "".join(f"\n  size {s}, proximity {p:.2f}" for s, p in result.pareto)
        QtWidgets.QMessageBox.information(
            Gui.getMainWindow(), "Optimize CSG tree",
            f"{root.Label}: size {result.size_before} -> {result.size_after}, "
            f"{result.primitives_before} -> {result.primitives_after} primitives, proximity "
            f"{result.proximity_before:.2f} -> {result.proximity_after:.2f}"
            + (f"\nPareto front (the GA):{front}" if front else ""))


_registered = False


def register():
    global _registered
    if not _registered:
        Gui.addCommand(IMAGE_TO_CSG, ImageToCsgCommand())
        Gui.addCommand(MESH_TO_CSG, MeshToCsgCommand())
        Gui.addCommand(RANGE_TO_CSG, RangeToCsgCommand())
        Gui.addCommand(MORPH_IMAGES, MorphImagesCommand())
        Gui.addCommand(EXPORT_SCAD, ExportScadCommand())
        Gui.addCommand(OPTIMIZE_TREE, OptimizeTreeCommand())
        _registered = True
