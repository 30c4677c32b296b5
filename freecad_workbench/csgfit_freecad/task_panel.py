"""The "Image to CSG" and "Mesh to CSG" task panels.

Both are FitPanels: the fit runs in a worker thread (the native module releases the GIL while it
solves); a QTimer on the GUI thread polls its progress and result, so every widget and document
change happens on the GUI thread. Cancel stops the solver through a csgfit.CancelToken (2D within
milliseconds, 3D within a second).
"""

import os
import threading
import time

import FreeCAD as App
import FreeCADGui as Gui
from PySide2 import QtCore, QtGui, QtWidgets

from . import builder, icon, import_csgfit

PRIMITIVES = ("rectangle", "circle", "ellipse", "triangle")
QUALITIES = ("fast", "default", "best", "paper")
IMAGE_FILTER = "Images (*.png *.jpg *.jpeg *.bmp *.pgm *.pbm *.ppm *.tga);;All files (*)"
PREVIEW_SIZE = 240


class FitJob:
    """One fit in a worker thread. Poll done(); then read result or error.

    fit: the csgfit function to run (fit_image by default, fit_mesh, fit_voxels); it is called
    as fit(source, progress=..., cancel=..., **options)."""

    def __init__(self, csgfit, source, options, fit=None):
        self.token = csgfit.CancelToken()
        self.progress = None  # latest csgfit.FitProgress (written by the solver thread)
        self.result = None
        self.error = None
        self._fit = fit or csgfit.fit_image
        self._source = source
        self._options = options
        self.started = None  # time.monotonic() at start()
        self._thread = threading.Thread(target=self._run, name="csgfit-fit", daemon=True)

    @property
    def options(self):
        return self._options

    def start(self):
        self.started = time.monotonic()
        self._thread.start()

    def _on_progress(self, p):
        self.progress = p
        return True

    def _run(self):
        try:
            self.result = self._fit(self._source, progress=self._on_progress, cancel=self.token,
                                    **self._options)
        except Exception as e:  # shown in the panel, never a traceback dialog
            self.error = e

    def done(self):
        return not self._thread.is_alive()

    def cancel(self, wait=0.0):
        self.token.cancel()
        if wait > 0:
            self._thread.join(wait)


def overlay_image(target, raster, size=PREVIEW_SIZE):
    """QImage of target and result overlaid: matched shape dark grey, excess (result only) red,
    uncovered (target only) blue, background white; the same colours as the CLI's --preview."""
    import numpy as np

    h, w = target.shape
    rgb = np.full((h, w, 3), 255, np.uint8)
    if raster is None:
        rgb[target] = (60, 60, 60)
    else:
        rgb[target & raster] = (60, 60, 60)
        rgb[raster & ~target] = (220, 40, 40)
        rgb[target & ~raster] = (40, 90, 230)
    rgb = np.ascontiguousarray(rgb)
    img = QtGui.QImage(rgb.data, w, h, 3 * w, QtGui.QImage.Format_RGB888).copy()
    return img.scaled(size, size, QtCore.Qt.KeepAspectRatio, QtCore.Qt.FastTransformation)


class FitPanel:
    """What Image to CSG and Mesh to CSG share: the native module, a FitJob polled by a QTimer,
    Fit / Cancel fit buttons, the progress bar and the status line, OK (build; before a fit:
    fit, then build) and Cancel (stop the fit, close).

    Subclasses make the form (calling _add_run_controls), and define fit_request() -> (fit
    function, source, options) or None after show_error, _fit_finished(result), build()."""

    TITLE = "CSG Fit"
    START_TEXT = "Choose an input, then Fit."

    def __init__(self):
        self.csgfit = None
        self.job = None
        self.result = None
        self.accept_when_done = False
        self.built = None  # builder.BuildResult after OK
        self.form = self._make_form()
        self.timer = QtCore.QTimer()
        self.timer.setInterval(100)
        self.timer.timeout.connect(self._poll)
        try:
            self.csgfit = import_csgfit()
        except ImportError as e:
            self.show_error(str(e))
            self.fit_button.setEnabled(False)

    def _make_form(self):
        raise NotImplementedError

    # ---- form pieces both panels use ------------------------------------------------------

    def _new_form(self, icon_name):
        form = QtWidgets.QWidget()
        form.setWindowTitle(self.TITLE)
        form.setWindowIcon(QtGui.QIcon(icon(icon_name)))
        return form, QtWidgets.QVBoxLayout(form)

    def _add_file_row(self, layout, placeholder):
        row = QtWidgets.QHBoxLayout()
        self.file_edit = QtWidgets.QLineEdit()
        self.file_edit.setPlaceholderText(placeholder)
        self.file_edit.editingFinished.connect(self._input_changed)
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._browse)
        row.addWidget(self.file_edit)
        row.addWidget(browse)
        layout.addLayout(row)

    def _add_search_rows(self, grid, time, min_time, k_max, k_tip):
        """Time budget (set self.quality between it and k yourself), then k and seed."""
        self.time = QtWidgets.QDoubleSpinBox()
        self.time.setRange(min_time, 3600)
        self.time.setValue(time)
        self.time.setSuffix(" s")
        grid.addRow("Time budget", self.time)
        self.k = QtWidgets.QDoubleSpinBox()
        self.k.setRange(-1, k_max)
        self.k.setValue(-1)
        self.k.setSpecialValueText("auto")
        self.k.setToolTip(k_tip)
        self.seed = QtWidgets.QSpinBox()
        self.seed.setRange(0, 2 ** 31 - 1)
        self.seed.setValue(1)

    def _add_preview(self, layout, tooltip):
        self.preview = QtWidgets.QLabel()
        self.preview.setAlignment(QtCore.Qt.AlignCenter)
        self.preview.setMinimumSize(PREVIEW_SIZE, 120)
        self.preview.setToolTip(tooltip)
        layout.addWidget(self.preview)

    @staticmethod
    def _add_legend(layout):
        legend = QtWidgets.QLabel(
            "<small>grey: matched &nbsp; <span style='color:#dc2828'>red: extra</span> &nbsp; "
            "<span style='color:#285ae6'>blue: missing</span></small>")
        legend.setAlignment(QtCore.Qt.AlignCenter)
        layout.addWidget(legend)
        layout.addStretch(1)

    def _add_run_controls(self, layout):
        row = QtWidgets.QHBoxLayout()
        self.fit_button = QtWidgets.QPushButton("Fit")
        self.fit_button.clicked.connect(self.start_fit)
        self.cancel_button = QtWidgets.QPushButton("Cancel fit")
        self.cancel_button.setEnabled(False)
        self.cancel_button.clicked.connect(self.cancel_fit)
        row.addWidget(self.fit_button)
        row.addWidget(self.cancel_button)
        layout.addLayout(row)
        self.progress_bar = QtWidgets.QProgressBar()
        self.progress_bar.setRange(0, 1000)
        self.progress_bar.setTextVisible(False)
        layout.addWidget(self.progress_bar)
        self.status = QtWidgets.QLabel(self.START_TEXT)
        self.status.setWordWrap(True)
        layout.addWidget(self.status)

    def getStandardButtons(self):
        return int(QtWidgets.QDialogButtonBox.Ok | QtWidgets.QDialogButtonBox.Cancel)

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        raise NotImplementedError

    def _fit_started(self):
        """Hook: forget the previous result's views."""

    def start_fit(self):
        """Starts the fit in a worker thread (returns at once); False if it could not start."""
        if self.csgfit is None or (self.job and not self.job.done()):
            return False
        request = self.fit_request()
        if request is None:
            return False
        fit, source, opts = request
        self.result = None
        self._fit_started()
        self.job = FitJob(self.csgfit, source, opts, fit=fit)
        self.job.start()
        self.fit_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.progress_bar.setValue(0)
        self.show_status("Fitting...")
        self.timer.start()
        return True

    def cancel_fit(self):
        if self.job and not self.job.done():
            self.accept_when_done = False
            self.job.cancel()
            self.show_status("Cancelling...")

    def is_running(self):
        return self.job is not None and not self.job.done()

    def _poll(self):
        job = self.job
        if job is None:
            self.timer.stop()
            return
        p = job.progress
        if p is not None:
            self.progress_bar.setValue(int(1000 * min(1.0, max(0.0, p.fraction))))
            if not job.done():
                self.show_status(f"Fitting... {p.seconds:.1f} s, {p.best_primitives} primitives,"
                                 f" score {p.best_score:.0f}")
        elif not job.done():
            # The 3D fit reports nothing while it voxelises and builds its first tree: show the
            # clock against the budget meanwhile.
            seconds = time.monotonic() - job.started
            budget = job.options.get("time") or 0
            if budget > 0:
                self.progress_bar.setValue(int(1000 * min(1.0, seconds / budget)))
            self.show_status(f"Fitting... {seconds:.1f} s (first tree)")
        if not job.done():
            return
        self.timer.stop()
        self.fit_button.setEnabled(True)
        self.cancel_button.setEnabled(False)
        if job.error is not None:
            self.accept_when_done = False
            self.progress_bar.setValue(0)
            self.show_error(str(job.error).splitlines()[0] if str(job.error)
                            else type(job.error).__name__)
            return
        self.result = job.result
        self.progress_bar.setValue(1000)
        s = self.result.stats
        self.show_status(f"IoU {s.iou:.4f}, {s.primitives} primitives, {s.seconds:.1f} s "
                         f"({s.stop_reason}).")
        self._fit_finished(self.result)
        if self.accept_when_done:
            self.accept_when_done = False
            self.accept()

    def _fit_finished(self, result):
        raise NotImplementedError

    def show_status(self, text):
        self.status.setStyleSheet("")
        self.status.setText(text)

    def show_error(self, text):
        self.status.setStyleSheet("color: #c0392b;")
        self.status.setText(text)

    # ---- OK / Cancel --------------------------------------------------------------------

    def build(self):
        raise NotImplementedError

    def _close(self):
        """Hook: drop previews before the panel closes."""

    def accept(self):
        if self.is_running():
            self.accept_when_done = True
            self.show_status("Fitting... the tree is added when the fit finishes.")
            return False
        if self.result is None:
            self.accept_when_done = True
            if not self.start_fit():
                self.accept_when_done = False
            return False
        try:
            self.build()
        except Exception as e:
            self.show_error(f"Could not build the FreeCAD tree: {e}")
            return False
        self.timer.stop()
        self._close()
        Gui.Control.closeDialog()
        return True

    def reject(self):
        if self.job is not None:
            self.job.cancel(wait=2.0)
        self.timer.stop()
        self._close()
        Gui.Control.closeDialog()
        return True


class ImageToCsgPanel(FitPanel):
    """Task panel: settings, Fit / Cancel, progress, preview, tree choice; OK builds the tree."""

    TITLE = "Image to CSG"
    START_TEXT = "Choose a bitmap, then Fit."

    def __init__(self, path=None):
        self.target = None
        super().__init__()
        if path:
            self.set_file(path)

    # ---- form ---------------------------------------------------------------------------

    def _make_form(self):
        form, layout = self._new_form("csgfit_image_to_csg")
        self._add_file_row(layout, "bitmap file (PNG, JPEG, BMP, PGM, TGA)")

        grid = QtWidgets.QFormLayout()
        self.threshold = QtWidgets.QSpinBox()
        self.threshold.setRange(-1, 255)
        self.threshold.setValue(-1)
        self.threshold.setSpecialValueText("auto (Otsu)")
        self.threshold.setToolTip("Grey level: darker or equal pixels are the shape")
        self.threshold.valueChanged.connect(self._input_changed)
        grid.addRow("Threshold", self.threshold)
        self.invert = QtWidgets.QCheckBox("Light pixels are the shape")
        self.invert.toggled.connect(self._input_changed)
        grid.addRow("Invert", self.invert)
        self.pixel_size = QtWidgets.QDoubleSpinBox()
        self.pixel_size.setRange(1e-4, 1e4)
        self.pixel_size.setDecimals(4)
        self.pixel_size.setValue(1.0)
        self.pixel_size.setSuffix(" mm")
        grid.addRow("Pixel size", self.pixel_size)
        self.thickness = QtWidgets.QDoubleSpinBox()
        self.thickness.setRange(0, 1e5)
        self.thickness.setDecimals(3)
        self.thickness.setSpecialValueText("auto (10 pixels)")
        self.thickness.setSuffix(" mm")
        grid.addRow("Thickness", self.thickness)
        self._add_search_rows(grid, 10, 0.1, 1e6, "Penalty per primitive: higher gives smaller trees")
        self.quality = QtWidgets.QComboBox()
        self.quality.addItems(QUALITIES)
        self.quality.setCurrentText("default")
        grid.addRow("Quality", self.quality)
        grid.addRow("Size weight k", self.k)
        prim_box = QtWidgets.QWidget()
        prim_row = QtWidgets.QHBoxLayout(prim_box)
        prim_row.setContentsMargins(0, 0, 0, 0)
        self.primitive_checks = {}
        for name in PRIMITIVES:
            cb = QtWidgets.QCheckBox(name)
            cb.setChecked(True)
            prim_row.addWidget(cb)
            self.primitive_checks[name] = cb
        grid.addRow("Primitives", prim_box)
        grid.addRow("Seed", self.seed)
        self.alternatives = QtWidgets.QSpinBox()
        self.alternatives.setRange(0, 10)
        self.alternatives.setValue(2)
        grid.addRow("Alternatives", self.alternatives)
        layout.addLayout(grid)

        self._add_run_controls(layout)

        self.tree_choice = QtWidgets.QComboBox()
        self.tree_choice.setEnabled(False)
        self.tree_choice.currentIndexChanged.connect(self._show_preview)
        layout.addWidget(self.tree_choice)
        self._add_preview(layout, "Grey: matched; red: result only; blue: image only")
        self._add_legend(layout)
        return form

    # ---- inputs -------------------------------------------------------------------------

    def set_file(self, path):
        self.file_edit.setText(path)
        self._input_changed()

    def _browse(self):
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self.form, "Bitmap to fit",
                                                        self.file_edit.text(), IMAGE_FILTER)
        if path:
            self.set_file(path)

    def options(self):
        """The fit_image keyword arguments the form describes."""
        prims = [n for n, cb in self.primitive_checks.items() if cb.isChecked()]
        return {
            "threshold": None if self.threshold.value() < 0 else self.threshold.value(),
            "invert": self.invert.isChecked(),
            "pixel_size": self.pixel_size.value(),
            "thickness": self.thickness.value(),
            "time": self.time.value(),
            "quality": self.quality.currentText(),
            "k": None if self.k.value() < 0 else self.k.value(),
            "primitives": prims,
            "seed": self.seed.value(),
            "alternatives": self.alternatives.value(),
        }

    def _input_changed(self, *_):
        """Shows the thresholded bitmap, so the user sees what will be fitted."""
        self.result = None
        self.tree_choice.clear()
        self.tree_choice.setEnabled(False)
        path = self.file_edit.text().strip()
        if not path or self.csgfit is None:
            return
        try:
            self.target = self.csgfit.load_bitmap(
                path, threshold=self.options()["threshold"], invert=self.invert.isChecked())
        except ValueError as e:
            self.target = None
            self.preview.clear()
            self.show_error(str(e))
            return
        h, w = self.target.shape
        self.show_status(f"{os.path.basename(path)}: {w} x {h} pixels, "
                         f"{int(self.target.sum())} shape pixels.")
        self.preview.setPixmap(QtGui.QPixmap.fromImage(overlay_image(self.target, None)))

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        path = self.file_edit.text().strip()
        if not path:
            self.show_error("Choose a bitmap file first.")
            return None
        opts = self.options()
        if not opts["primitives"]:
            self.show_error("Select at least one primitive type.")
            return None
        return self.csgfit.fit_image, path, opts

    def _fit_started(self):
        self.tree_choice.clear()
        self.tree_choice.setEnabled(False)

    def _fit_finished(self, result):
        self.target = result.target()
        s = result.stats
        self.tree_choice.blockSignals(True)
        self.tree_choice.clear()
        self.tree_choice.addItem(f"Best: {s.primitives} primitives, IoU {s.iou:.4f}")
        for i, alt in enumerate(result.alternatives):
            self.tree_choice.addItem(f"Alternative {i + 1}: {alt.stats.primitives} primitives,"
                                     f" IoU {alt.stats.iou:.4f}")
        self.tree_choice.blockSignals(False)
        self.tree_choice.setEnabled(self.tree_choice.count() > 1)
        self._show_preview()

    def chosen_alternative(self):
        """-1 for the best tree, else the index of the chosen alternative."""
        return max(0, self.tree_choice.currentIndex()) - 1

    def _show_preview(self, *_):
        if self.result is None:
            return
        i = self.chosen_alternative()
        raster = self.result.raster() if i < 0 else self.result.alternatives[i].raster()
        self.preview.setPixmap(QtGui.QPixmap.fromImage(overlay_image(self.target, raster)))

    # ---- OK / Cancel --------------------------------------------------------------------

    def build(self):
        """Builds the chosen tree into the active document (a new one if there is none)."""
        doc = App.ActiveDocument or App.newDocument()
        name = os.path.splitext(os.path.basename(self.file_edit.text().strip()))[0]
        thickness = self.thickness.value() or None
        doc.openTransaction("Image to CSG")
        try:
            self.built = builder.build(doc, self.result, thickness=thickness,
                                       label=name or None, alternative=self.chosen_alternative())
        finally:
            doc.commitTransaction()
        if Gui.ActiveDocument is not None:
            view = Gui.ActiveDocument.ActiveView
            if hasattr(view, "viewIsometric"):
                view.viewIsometric()
                view.fitAll()
        return self.built


# ---- Mesh to CSG ------------------------------------------------------------------------------

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
    START_TEXT = "Select a mesh or choose a file, then Fit."

    def __init__(self, mesh_object=None, path=None):
        self.mesh_object = mesh_object
        self.overlay = ShapeOverlay()
        self._mesh_mode = None  # the mesh's display mode while it is shown as wireframe
        self.preview_shape = None
        self.target = None
        self.raster = None
        super().__init__()
        if mesh_object is not None:
            self.file_edit.setText("")
            self.file_edit.setPlaceholderText(f"mesh object: {mesh_object.Label}")
            self.show_status(f"{mesh_object.Label}: {mesh_object.Mesh.CountFacets} triangles. "
                             "Fit when ready.")
        if path:
            self.set_file(path)

    def _make_form(self):
        form, layout = self._new_form("csgfit_mesh_to_csg")
        self._add_file_row(layout, "mesh or voxel file (STL, OBJ, OFF, PLY, NPY, BINVOX)")

        grid = QtWidgets.QFormLayout()
        self._add_search_rows(grid, 20, 0.5, 1e9,
                              "Penalty per primitive in voxels: higher gives smaller trees")
        self.quality = QtWidgets.QComboBox()
        for text, _ in MESH_QUALITIES:
            self.quality.addItem(text)
        self.quality.setCurrentIndex(1)
        self.quality.setToolTip("How finely the mesh is voxelised before the fit")
        grid.addRow("Quality", self.quality)
        grid.addRow("Size weight k", self.k)
        prim_box = QtWidgets.QWidget()
        prim_grid = QtWidgets.QGridLayout(prim_box)
        prim_grid.setContentsMargins(0, 0, 0, 0)
        self.primitive_checks = {}
        for n, name in enumerate(PRIMITIVES_3D):
            cb = QtWidgets.QCheckBox(name)
            cb.setChecked(name != "torus")  # the CLI's default set
            if name == "box":
                cb.setEnabled(False)  # the 3D search builds on boxes
                cb.setToolTip("The 3D fit always uses boxes")
            prim_grid.addWidget(cb, n // 4, n % 4)
            self.primitive_checks[name] = cb
        grid.addRow("Primitives", prim_box)
        grid.addRow("Seed", self.seed)
        layout.addLayout(grid)

        self._add_run_controls(layout)

        self.show_3d = QtWidgets.QCheckBox("Show the fitted tree in the 3D view")
        self.show_3d.setChecked(True)
        self.show_3d.toggled.connect(self._show_overlay)
        layout.addWidget(self.show_3d)
        self._add_preview(layout, "A z slice of the voxels: grey matched; red: tree only; "
                                  "blue: mesh only")
        row = QtWidgets.QHBoxLayout()
        row.addWidget(QtWidgets.QLabel("Slice z"))
        self.slice = QtWidgets.QSlider(QtCore.Qt.Horizontal)
        self.slice.setEnabled(False)
        self.slice.valueChanged.connect(self._show_slice)
        row.addWidget(self.slice)
        layout.addLayout(row)
        self._add_legend(layout)
        return form

    # ---- inputs -------------------------------------------------------------------------

    def set_file(self, path):
        """Fit a file instead of the selected mesh object."""
        self.mesh_object = None
        self.file_edit.setText(path)
        self._input_changed()

    def _browse(self):
        from .mesh_input import FILE_FILTER

        path, _ = QtWidgets.QFileDialog.getOpenFileName(self.form, "Mesh or voxels to fit",
                                                        self.file_edit.text(), FILE_FILTER)
        if path:
            self.set_file(path)

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
        return {
            "time": self.time.value(),
            "resolution": MESH_QUALITIES[self.quality.currentIndex()][1],
            "k": None if self.k.value() < 0 else self.k.value(),
            "primitives": [n for n, cb in self.primitive_checks.items() if cb.isChecked()],
            "seed": self.seed.value(),
        }

    def source_name(self):
        if self.mesh_object is not None:
            return self.mesh_object.Label
        return os.path.splitext(os.path.basename(self.file_edit.text().strip()))[0]

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        opts = self.options()
        if self.mesh_object is not None:
            from .mesh_input import arrays_from_mesh

            try:
                source = arrays_from_mesh(self.mesh_object)
            except Exception as e:  # a deleted object, an empty mesh
                self.show_error(f"cannot read the mesh object: {e}")
                return None
            if len(source[1]) == 0:
                self.show_error(f"{self.mesh_object.Label} has no triangles.")
                return None
        else:
            source = self.file_edit.text().strip()
            if not source:
                self.show_error("Select a mesh object or choose a file first.")
                return None
        return self.csgfit.fit_mesh, source, opts

    def _fit_started(self):
        self._clear_preview()

    def _fit_finished(self, result):
        self.target = result.target()
        self.raster = result.raster()
        s = result.stats
        text = self.status.text()
        if result.warning:
            text += " Note: " + result.warning
        self.show_status(text)
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
            self.show_error(f"IoU {s.iou:.4f}, but the tree does not build in FreeCAD: {e}")
        self._show_overlay()

    def _show_slice(self, *_):
        if self.target is None:
            return
        k = self.slice.value()
        t, r = slice_images(self.target, self.raster, k)
        self.preview.setPixmap(QtGui.QPixmap.fromImage(overlay_image(t, r)))
        self.slice.setToolTip(f"voxel layer {k} of {self.target.shape[2]}")

    def _show_overlay(self, *_):
        self.overlay.clear()
        if self.preview_shape is None or not self.show_3d.isChecked():
            self._mesh_as_wireframe(False)
            return
        if Gui.ActiveDocument is None:
            # A file fitted with no document open: the tree will go into a new one anyway.
            App.newDocument(builder._object_name(self.source_name() or "csgfit"))
        self._mesh_as_wireframe(True)
        if self.overlay.show(self.preview_shape):
            view = Gui.ActiveDocument.ActiveView
            if hasattr(view, "viewIsometric"):
                view.viewIsometric()
                view.fitAll()

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

    def build(self):
        """Builds the fitted tree into the mesh object's document (else the active one, else a
        new one) and hides the mesh, which the solid now stands for."""
        doc = (self.mesh_object.Document if self.mesh_object is not None else None) \
            or App.ActiveDocument or App.newDocument()
        doc.openTransaction("Mesh to CSG")
        try:
            # Labels are unique in a document: the mesh object keeps its own.
            label = (f"{self.mesh_object.Label} CSG" if self.mesh_object is not None
                     else self.source_name() or None)
            self.built = builder.build(doc, self.result, label=label)
            if self.mesh_object is not None and getattr(self.mesh_object, "ViewObject", None):
                self.mesh_object.ViewObject.Visibility = False
        finally:
            doc.commitTransaction()
        if Gui.ActiveDocument is not None:
            view = Gui.ActiveDocument.ActiveView
            if hasattr(view, "viewIsometric"):
                view.viewIsometric()
                view.fitAll()
        return self.built

    def _close(self):
        self.overlay.clear()
        try:
            self._mesh_as_wireframe(False)
        except Exception:  # the mesh object was deleted meanwhile
            pass
