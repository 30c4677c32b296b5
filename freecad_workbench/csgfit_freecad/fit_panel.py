"""What the Image to CSG and Mesh to CSG task panels share: the fit in a worker thread, the
form rows both have, the preview picture, and OK / Cancel.

The fit runs in a worker thread (the native module releases the GIL while it solves); a QTimer
on the GUI thread polls its progress and result, so every widget and document change happens
on the GUI thread. Cancel stops the solver through a csgfit.CancelToken (2D within
milliseconds, 3D within a second).
"""

import time

import FreeCAD as App
import FreeCADGui as Gui
from .qt import QtCore, QtGui, QtWidgets

from . import icon, import_csgfit
from .fit_job import FitJob

PREVIEW_SIZE = 240


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


def view_all():
    """An isometric view of everything in the active 3D view (after a build or a preview)."""
    if Gui.ActiveDocument is None:
        return
    view = Gui.ActiveDocument.ActiveView
    if hasattr(view, "viewIsometric"):
        view.viewIsometric()
        view.fitAll()


class FitPanel:
    """The shared panel: the native module, a FitJob polled by a QTimer, the input file row,
    the search rows, Fit / Cancel fit buttons, the progress bar and the status line, the
    preview, OK (build; before a fit: fit, then build) and Cancel (stop the fit, close).

    Subclasses set the class attributes below and define _add_settings(grid) (with
    _add_search_rows), _add_views(layout) (with _add_preview), fit_request() -> (fit function,
    source, options) or None after show_error, _fit_finished(result), _input_changed() and
    build_tree(doc)."""

    TITLE = "CSG Fit"
    ICON = "csgfit_workbench"
    START_TEXT = "Choose an input, then Fit."
    FILE_PLACEHOLDER = "file to fit"
    BROWSE_TITLE = "Input to fit"
    FILE_FILTER = "All files (*)"

    def __init__(self, path=None):
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
        if path:
            self.set_file(path)

    # ---- the form rows both panels have ---------------------------------------------------

    def _make_form(self):
        """The input file row, the settings, Fit / Cancel fit and the status, the views."""
        form = QtWidgets.QWidget()
        form.setWindowTitle(self.TITLE)
        form.setWindowIcon(QtGui.QIcon(icon(self.ICON)))
        layout = QtWidgets.QVBoxLayout(form)
        self._add_file_row(layout)
        grid = QtWidgets.QFormLayout()
        self._add_settings(grid)
        layout.addLayout(grid)
        self._add_run_controls(layout)
        self._add_views(layout)
        return form

    def _add_settings(self, grid):
        raise NotImplementedError

    def _add_views(self, layout):
        raise NotImplementedError

    def _add_file_row(self, layout):
        row = QtWidgets.QHBoxLayout()
        self.file_edit = QtWidgets.QLineEdit()
        self.file_edit.setPlaceholderText(self.FILE_PLACEHOLDER)
        self.file_edit.editingFinished.connect(self._input_changed)
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._browse)
        row.addWidget(self.file_edit)
        row.addWidget(browse)
        layout.addLayout(row)

    def _browse(self):
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self.form, self.BROWSE_TITLE,
                                                        self.file_edit.text(), self.FILE_FILTER)
        if path:
            self.set_file(path)

    def set_file(self, path):
        """Fit this file."""
        self.file_edit.setText(path)
        self._input_changed()

    def _add_search_rows(self, grid, time, min_time, qualities, k_max, k_tip, primitives):
        """Time budget, Quality (qualities: item texts, the default one, a tooltip), Size
        weight k, Primitives (primitives: (name, checked, enabled) triples), Seed."""
        self._add_time_row(grid, time, min_time)
        items, default, tip = qualities
        self.quality = QtWidgets.QComboBox()
        self.quality.addItems(list(items))
        self.quality.setCurrentText(default)
        self.quality.setToolTip(tip)
        grid.addRow("Quality", self.quality)
        self.k = QtWidgets.QDoubleSpinBox()
        self.k.setRange(-1, k_max)
        self.k.setValue(-1)
        self.k.setSpecialValueText("auto")
        self.k.setToolTip(k_tip)
        grid.addRow("Size weight k", self.k)
        grid.addRow("Primitives", self._primitive_boxes(primitives))
        self._add_seed_row(grid)

    def _add_time_row(self, grid, time, min_time):
        """Time budget in seconds (at most an hour)."""
        self.time = QtWidgets.QDoubleSpinBox()
        self.time.setRange(min_time, 3600)
        self.time.setValue(time)
        self.time.setSuffix(" s")
        grid.addRow("Time budget", self.time)

    def _add_seed_row(self, grid):
        """Seed: the same seed and threads give the same tree."""
        self.seed = QtWidgets.QSpinBox()
        self.seed.setRange(0, 2 ** 31 - 1)
        self.seed.setValue(1)
        grid.addRow("Seed", self.seed)

    def _primitive_boxes(self, primitives):
        box = QtWidgets.QWidget()
        cells = QtWidgets.QGridLayout(box)
        cells.setContentsMargins(0, 0, 0, 0)
        self.primitive_checks = {}
        for n, (name, checked, enabled) in enumerate(primitives):
            cb = QtWidgets.QCheckBox(name)
            cb.setChecked(checked)
            cb.setEnabled(enabled)
            cells.addWidget(cb, n // 4, n % 4)
            self.primitive_checks[name] = cb
        return box

    def search_options(self):
        """The fit keyword arguments of the search rows (quality is the panel's own)."""
        return {
            "time": self.time.value(),
            "k": None if self.k.value() < 0 else self.k.value(),
            "primitives": [n for n, cb in self.primitive_checks.items() if cb.isChecked()],
            "seed": self.seed.value(),
        }

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

    def _add_preview(self, layout, tooltip, below=None):
        """The overlay picture, then the widgets of `below` (a layout or None), then the
        colour legend."""
        self.preview = QtWidgets.QLabel()
        self.preview.setAlignment(QtCore.Qt.AlignCenter)
        self.preview.setMinimumSize(PREVIEW_SIZE, 120)
        self.preview.setToolTip(tooltip)
        layout.addWidget(self.preview)
        if below is not None:
            layout.addLayout(below)
        legend = QtWidgets.QLabel(
            "<small>grey: matched &nbsp; <span style='color:#dc2828'>red: extra</span> &nbsp; "
            "<span style='color:#285ae6'>blue: missing</span></small>")
        legend.setAlignment(QtCore.Qt.AlignCenter)
        layout.addWidget(legend)
        layout.addStretch(1)

    def show_overlay(self, target, raster):
        """Shows target and raster (2D bool masks) overlaid in the preview."""
        self.preview.setPixmap(QtGui.QPixmap.fromImage(overlay_image(target, raster)))

    def getStandardButtons(self):
        return int(QtWidgets.QDialogButtonBox.Ok | QtWidgets.QDialogButtonBox.Cancel)

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        raise NotImplementedError

    def _input_changed(self, *_):
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
        self.job = FitJob(self.csgfit, fit, source, opts)
        self.job.start()
        self.fit_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.progress_bar.setValue(0)
        self.show_status("Fitting...")
        self.timer.start()
        return True

    def cancel_fit(self):
        """Stops a running fit; it ends with the best tree found so far."""
        if self.job and not self.job.done():
            self.accept_when_done = False
            self.job.cancel()
            self.show_status("Cancelling...")

    def is_running(self):
        """Whether a fit is running."""
        return self.job is not None and not self.job.done()

    def _show_progress(self, job):
        p = job.progress
        if p is not None:
            self.progress_bar.setValue(int(1000 * min(1.0, max(0.0, p.fraction))))
            self.show_status(f"Fitting... {p.seconds:.1f} s, {p.best_primitives} primitives,"
                             f" score {p.best_score:.0f}")
            return
        # The 3D fit reports nothing while it voxelises and builds its first tree: show the
        # clock against the budget meanwhile.
        seconds = time.monotonic() - job.started
        budget = job.options.get("time") or 0
        if budget > 0:
            self.progress_bar.setValue(int(1000 * min(1.0, seconds / budget)))
        self.show_status(f"Fitting... {seconds:.1f} s (first tree)")

    def _poll(self):
        job = self.job
        if job is None:
            self.timer.stop()
            return
        if not job.done():
            self._show_progress(job)
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
        self.show_status(self.summary(self.result))
        self._fit_finished(self.result)
        if self.accept_when_done:
            self.accept_when_done = False
            self.accept()

    def _fit_finished(self, result):
        raise NotImplementedError

    def summary(self, result):
        """The status line once the fit has ended."""
        s = result.stats
        return (f"IoU {s.iou:.4f}, {s.primitives} primitives, {s.seconds:.1f} s "
                f"({s.stop_reason}).")

    def show_status(self, text):
        """A normal message in the status line."""
        self.status.setStyleSheet("")
        self.status.setText(text)

    def show_error(self, text):
        """An error in the status line, in red."""
        self.status.setStyleSheet("color: #c0392b;")
        self.status.setText(text)

    # ---- OK / Cancel --------------------------------------------------------------------

    def target_document(self):
        """The document the tree goes into."""
        return App.ActiveDocument or App.newDocument()

    def build_tree(self, doc):
        """Builds the fitted tree into doc (inside the panel's undo step); a BuildResult."""
        raise NotImplementedError

    def build(self):
        """Builds the fitted tree as one undo step and shows it."""
        doc = self.target_document()
        doc.openTransaction(self.TITLE)
        try:
            self.built = self.build_tree(doc)
        finally:
            doc.commitTransaction()
        view_all()
        return self.built

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
