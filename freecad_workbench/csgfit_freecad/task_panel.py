"""The "Image to CSG" task panel.

The fit runs in a worker thread (the native module releases the GIL while it solves); a QTimer
on the GUI thread polls its progress and result, so every widget and document change happens on
the GUI thread. Cancel stops the solver through a csgfit.CancelToken within milliseconds.
"""

import os
import threading

import FreeCAD as App
import FreeCADGui as Gui
from PySide2 import QtCore, QtGui, QtWidgets

from . import builder, icon, import_csgfit

PRIMITIVES = ("rectangle", "circle", "ellipse", "triangle")
QUALITIES = ("fast", "default", "best", "paper")
IMAGE_FILTER = "Images (*.png *.jpg *.jpeg *.bmp *.pgm *.pbm *.ppm *.tga);;All files (*)"
PREVIEW_SIZE = 240


class FitJob:
    """One fit in a worker thread. Poll done(); then read result or error."""

    def __init__(self, csgfit, image, options):
        self.token = csgfit.CancelToken()
        self.progress = None  # latest csgfit.FitProgress (written by the solver thread)
        self.result = None
        self.error = None
        self._csgfit = csgfit
        self._image = image
        self._options = options
        self._thread = threading.Thread(target=self._run, name="csgfit-fit", daemon=True)

    def start(self):
        self._thread.start()

    def _on_progress(self, p):
        self.progress = p
        return True

    def _run(self):
        try:
            self.result = self._csgfit.fit_image(self._image, progress=self._on_progress,
                                                 cancel=self.token, **self._options)
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


class ImageToCsgPanel:
    """Task panel: settings, Fit / Cancel, progress, preview, tree choice; OK builds the tree."""

    def __init__(self, path=None):
        self.csgfit = None
        self.job = None
        self.result = None
        self.target = None
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
        if path:
            self.set_file(path)

    # ---- form ---------------------------------------------------------------------------

    def _make_form(self):
        form = QtWidgets.QWidget()
        form.setWindowTitle("Image to CSG")
        form.setWindowIcon(QtGui.QIcon(icon("csgfit_image_to_csg")))
        layout = QtWidgets.QVBoxLayout(form)

        row = QtWidgets.QHBoxLayout()
        self.file_edit = QtWidgets.QLineEdit()
        self.file_edit.setPlaceholderText("bitmap file (PNG, JPEG, BMP, PGM, TGA)")
        self.file_edit.editingFinished.connect(self._input_changed)
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._browse)
        row.addWidget(self.file_edit)
        row.addWidget(browse)
        layout.addLayout(row)

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
        self.time = QtWidgets.QDoubleSpinBox()
        self.time.setRange(0.1, 3600)
        self.time.setValue(10)
        self.time.setSuffix(" s")
        grid.addRow("Time budget", self.time)
        self.quality = QtWidgets.QComboBox()
        self.quality.addItems(QUALITIES)
        self.quality.setCurrentText("default")
        grid.addRow("Quality", self.quality)
        self.k = QtWidgets.QDoubleSpinBox()
        self.k.setRange(-1, 1e6)
        self.k.setValue(-1)
        self.k.setSpecialValueText("auto")
        self.k.setToolTip("Penalty per primitive: higher gives smaller trees")
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
        self.seed = QtWidgets.QSpinBox()
        self.seed.setRange(0, 2 ** 31 - 1)
        self.seed.setValue(1)
        grid.addRow("Seed", self.seed)
        self.alternatives = QtWidgets.QSpinBox()
        self.alternatives.setRange(0, 10)
        self.alternatives.setValue(2)
        grid.addRow("Alternatives", self.alternatives)
        layout.addLayout(grid)

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
        self.status = QtWidgets.QLabel("Choose a bitmap, then Fit.")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)

        self.tree_choice = QtWidgets.QComboBox()
        self.tree_choice.setEnabled(False)
        self.tree_choice.currentIndexChanged.connect(self._show_preview)
        layout.addWidget(self.tree_choice)
        self.preview = QtWidgets.QLabel()
        self.preview.setAlignment(QtCore.Qt.AlignCenter)
        self.preview.setMinimumSize(PREVIEW_SIZE, 120)
        self.preview.setToolTip("Grey: matched; red: result only; blue: image only")
        layout.addWidget(self.preview)
        legend = QtWidgets.QLabel(
            "<small>grey: matched &nbsp; <span style='color:#dc2828'>red: extra</span> &nbsp; "
            "<span style='color:#285ae6'>blue: missing</span></small>")
        legend.setAlignment(QtCore.Qt.AlignCenter)
        layout.addWidget(legend)
        layout.addStretch(1)
        return form

    def getStandardButtons(self):
        return int(QtWidgets.QDialogButtonBox.Ok | QtWidgets.QDialogButtonBox.Cancel)

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

    def start_fit(self):
        """Starts the fit in a worker thread (returns at once); False if it could not start."""
        if self.csgfit is None or (self.job and not self.job.done()):
            return False
        path = self.file_edit.text().strip()
        if not path:
            self.show_error("Choose a bitmap file first.")
            return False
        opts = self.options()
        if not opts["primitives"]:
            self.show_error("Select at least one primitive type.")
            return False
        self.result = None
        self.tree_choice.clear()
        self.tree_choice.setEnabled(False)
        self.job = FitJob(self.csgfit, path, opts)
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
        self.target = self.result.target()
        self.progress_bar.setValue(1000)
        s = self.result.stats
        self.show_status(f"IoU {s.iou:.4f}, {s.primitives} primitives, {s.seconds:.1f} s "
                         f"({s.stop_reason}).")
        self.tree_choice.blockSignals(True)
        self.tree_choice.clear()
        self.tree_choice.addItem(f"Best: {s.primitives} primitives, IoU {s.iou:.4f}")
        for i, alt in enumerate(self.result.alternatives):
            self.tree_choice.addItem(f"Alternative {i + 1}: {alt.stats.primitives} primitives,"
                                     f" IoU {alt.stats.iou:.4f}")
        self.tree_choice.blockSignals(False)
        self.tree_choice.setEnabled(self.tree_choice.count() > 1)
        self._show_preview()
        if self.accept_when_done:
            self.accept_when_done = False
            self.accept()

    def chosen_alternative(self):
        """-1 for the best tree, else the index of the chosen alternative."""
        return max(0, self.tree_choice.currentIndex()) - 1

    def _show_preview(self, *_):
        if self.result is None:
            return
        i = self.chosen_alternative()
        raster = self.result.raster() if i < 0 else self.result.alternatives[i].raster()
        self.preview.setPixmap(QtGui.QPixmap.fromImage(overlay_image(self.target, raster)))

    def show_status(self, text):
        self.status.setStyleSheet("")
        self.status.setText(text)

    def show_error(self, text):
        self.status.setStyleSheet("color: #c0392b;")
        self.status.setText(text)

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
        Gui.Control.closeDialog()
        return True

    def reject(self):
        if self.job is not None:
            self.job.cancel(wait=2.0)
        self.timer.stop()
        Gui.Control.closeDialog()
        return True
