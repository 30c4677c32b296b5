"""The "Mesh to CSG" task panel: a selected mesh object or a mesh / voxel file, the search
settings, a z slice of the voxels against the tree's, and the fitted tree drawn over the mesh
in the 3D view."""

import os

import FreeCAD as App
import FreeCADGui as Gui
from .qt import QtCore, QtWidgets

from . import builder
from .fit_panel import FitPanel, view_all
from .mesh_input import FILE_FILTER

PRIMITIVES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "prism", "torus")
#: Quality = how finely the mesh is voxelised (the 3D search has no other settings yet):
#: voxels along the longest side, 0 = the CLI's automatic size.
MESH_QUALITIES = (("fast (64 voxels)", 64), ("default (auto)", 0), ("best (256 voxels)", 256))


def slice_images(target, raster, k):
    """(target, raster) z-slice k of two voxel arrays [i, j, k] as image masks (row 0 on top,
    y up), for overlay_image."""
    t = target[:, :, k].T[::-1]
    r = None if raster is None else raster[:, :, k].T[::-1]
    return t, r


class ShapeOverlay:
    """A shape drawn in the 3D view as a translucent Coin node, outside the document (no
    object, no undo step): the fitted tree over the mesh while the panel is open."""

    def __init__(self):
        self.node = None
        self.view = None

    def show(self, shape, colour=(0.15, 0.55, 0.9), transparency=0.35):
        """Draws shape in the active view; False when there is none or the shape is empty."""
        self.clear()
        if Gui.ActiveDocument is None or shape is None or shape.isNull():
            return False
        from pivy import coin

        points, triangles = shape.tessellate(max(shape.BoundBox.DiagonalLength, 1e-9) * 1e-3)
        sep = coin.SoSeparator()
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        hints.shapeType = coin.SoShapeHints.SOLID
        mat = coin.SoMaterial()
        mat.diffuseColor.setValue(*colour)
        mat.transparency.setValue(transparency)
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(points), [(p.x, p.y, p.z) for p in points])
        faces = coin.SoIndexedFaceSet()
        index = []
        for a, b, c in triangles:
            index += [a, b, c, -1]
        faces.coordIndex.setValues(0, len(index), index)
        for child in (hints, mat, coords, faces):
            sep.addChild(child)
        self.view = Gui.ActiveDocument.ActiveView
        self.view.getSceneGraph().addChild(sep)
        self.node = sep
        return True

    def clear(self):
        """Removes the drawn shape, if any."""
        if self.node is not None and self.view is not None:
            try:
                self.view.getSceneGraph().removeChild(self.node)
            except Exception:  # the view was closed meanwhile
                pass
        self.node = None
        self.view = None


class MeshToCsgPanel(FitPanel):
    """Task panel: a selected mesh object or a mesh/voxel file, settings, Fit / Cancel,
    progress, preview (a z slice of the voxels against the tree's, and the fitted tree drawn
    in the 3D view); OK builds the tree next to the mesh."""

    TITLE = "Mesh to CSG"
    ICON = "csgfit_mesh_to_csg"
    START_TEXT = "Select a mesh or choose a file, then Fit."
    FILE_PLACEHOLDER = "mesh or voxel file (STL, OBJ, OFF, PLY, NPY, BINVOX)"
    BROWSE_TITLE = "Mesh or voxels to fit"
    FILE_FILTER = FILE_FILTER

    def __init__(self, mesh_object=None, path=None):
        self.mesh_object = mesh_object
        self.overlay = ShapeOverlay()
        self._mesh_mode = None  # the mesh's display mode while it is shown as wireframe
        self.preview_shape = None
        self.target = None
        self.raster = None
        super().__init__(path)
        if self.mesh_object is not None:
            self.file_edit.setPlaceholderText(f"mesh object: {mesh_object.Label}")
            self.show_status(f"{mesh_object.Label}: {mesh_object.Mesh.CountFacets} triangles. "
                             "Fit when ready.")

    def _add_settings(self, grid):
        # Boxes stay on: the 3D search builds on them. The torus is off, as in the CLI.
        self._add_search_rows(
            grid, 20, 0.5, ([text for text, _ in MESH_QUALITIES], MESH_QUALITIES[1][0],
                            "How finely the mesh is voxelised before the fit"),
            1e9, "Penalty per primitive in voxels: higher gives smaller trees",
            [(name, name != "torus", name != "box") for name in PRIMITIVES_3D])
        self.primitive_checks["box"].setToolTip("The 3D fit always uses boxes")
        self.construct = QtWidgets.QCheckBox("Build from the mesh's faces first")
        self.construct.setChecked(True)
        self.construct.setToolTip("Read the mesh's planes, cylinders, cones, spheres and tori and "
                                  "build the tree from them; off: search the voxels only")
        grid.addRow("Construction", self.construct)

    def _add_views(self, layout):
        self.show_3d = QtWidgets.QCheckBox("Show the fitted tree in the 3D view")
        self.show_3d.setChecked(True)
        self.show_3d.toggled.connect(self._show_overlay)
        layout.addWidget(self.show_3d)
        row = QtWidgets.QHBoxLayout()
        row.addWidget(QtWidgets.QLabel("Slice z"))
        self.slice = QtWidgets.QSlider(QtCore.Qt.Horizontal)
        self.slice.setEnabled(False)
        self.slice.valueChanged.connect(self._show_slice)
        row.addWidget(self.slice)
        self._add_preview(layout, "A z slice of the voxels: grey matched; red: tree only; "
                                  "blue: mesh only", below=row)

    # ---- inputs -------------------------------------------------------------------------

    def set_file(self, path):
        """Fit a file instead of the selected mesh object."""
        self.mesh_object = None
        super().set_file(path)

    def _input_changed(self, *_):
        self.result = None
        self._clear_preview()
        path = self.file_edit.text().strip()
        if not path:
            return
        self.mesh_object = None
        if not os.path.isfile(path):
            self.show_error(f"cannot open '{path}': no such file")
            return
        from .mesh_input import is_fit_input

        if not is_fit_input(path):
            self.show_error(f"unknown input format '{path}' (expected .stl, .obj, .off, .ply, "
                            ".npy or .binvox)")
            return
        self.show_status(f"{os.path.basename(path)}: Fit when ready.")

    def options(self):
        """The fit_mesh keyword arguments the form describes."""
        return dict(self.search_options(),
                    resolution=MESH_QUALITIES[self.quality.currentIndex()][1],
                    construct=self.construct.isChecked())

    def source_name(self):
        """The mesh object's label, or the file's stem."""
        if self.mesh_object is not None:
            return self.mesh_object.Label
        return os.path.splitext(os.path.basename(self.file_edit.text().strip()))[0]

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        if self.mesh_object is None:
            source = self.file_edit.text().strip()
            if not source:
                self.show_error("Select a mesh object or choose a file first.")
                return None
            return self.csgfit.fit_mesh, source, self.options()
        from .mesh_input import arrays_from_mesh

        try:
            source = arrays_from_mesh(self.mesh_object)
        except Exception as e:  # a deleted object, an empty mesh
            self.show_error(f"cannot read the mesh object: {e}")
            return None
        if len(source[1]) == 0:
            self.show_error(f"{self.mesh_object.Label} has no triangles.")
            return None
        return self.csgfit.fit_mesh, source, self.options()

    def _fit_started(self):
        self._clear_preview()

    def _fit_finished(self, result):
        self.target = result.target()
        self.raster = result.raster()
        if result.warning:
            self.show_status(self.status.text() + " Note: " + result.warning)
        nz = self.target.shape[2]
        self.slice.blockSignals(True)
        self.slice.setRange(0, nz - 1)
        self.slice.setValue(nz // 2)
        self.slice.blockSignals(False)
        self.slice.setEnabled(True)
        self._show_slice()
        try:
            self.preview_shape = builder.preview_shape(result)
        except Exception as e:
            self.preview_shape = None
            self.show_error(f"IoU {result.stats.iou:.4f}, but the tree does not build in "
                            f"FreeCAD: {e}")
        self._show_overlay()

    def _show_slice(self, *_):
        if self.target is None:
            return
        k = self.slice.value()
        self.show_overlay(*slice_images(self.target, self.raster, k))
        self.slice.setToolTip(f"voxel layer {k} of {self.target.shape[2]}")

    def _show_overlay(self, *_):
        self.overlay.clear()
        if self.preview_shape is None or not self.show_3d.isChecked():
            self._mesh_as_wireframe(False)
            return
        if Gui.ActiveDocument is None:
            # A file fitted with no document open: the tree will go into a new one anyway.
            App.newDocument(builder.object_name(self.source_name() or "csgfit"))
        self._mesh_as_wireframe(True)
        if self.overlay.show(self.preview_shape):
            view_all()

    def _mesh_as_wireframe(self, on):
        """The mesh drawn as wireframe while the tree is overlaid (shaded, the coinciding
        surfaces would z-fight); restored when the preview goes."""
        vo = getattr(self.mesh_object, "ViewObject", None) if self.mesh_object else None
        if vo is None or "Wireframe" not in vo.listDisplayModes():
            return
        if on and self._mesh_mode is None:
            self._mesh_mode = vo.DisplayMode
            vo.DisplayMode = "Wireframe"
        elif not on and self._mesh_mode is not None:
            vo.DisplayMode = self._mesh_mode
            self._mesh_mode = None

    def _clear_preview(self):
        self._mesh_as_wireframe(False)
        self.overlay.clear()
        self.preview_shape = None
        self.target = self.raster = None
        self.preview.clear()
        self.slice.setEnabled(False)

    # ---- OK / Cancel --------------------------------------------------------------------

    def target_document(self):
        """The mesh object's document, else the active one, else a new one."""
        doc = self.mesh_object.Document if self.mesh_object is not None else None
        return doc or super().target_document()

    def build_tree(self, doc):
        """The fitted tree, next to the mesh, which is hidden: the solid now stands for it."""
        # Labels are unique in a document: the mesh object keeps its own.
        label = (f"{self.mesh_object.Label} CSG" if self.mesh_object is not None
                 else self.source_name() or None)
        built = builder.build(doc, self.result, label=label)
        if self.mesh_object is not None and getattr(self.mesh_object, "ViewObject", None):
            self.mesh_object.ViewObject.Visibility = False
        return built

    def _close(self):
        self.overlay.clear()
        try:
            self._mesh_as_wireframe(False)
        except Exception:  # the mesh object was deleted meanwhile
            pass
