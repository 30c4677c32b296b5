"""The "Range image to CSG" task panel (seed 002): one or more range images or point clouds of
one part, the sensor's fields read from the first image's sidecar and editable to override it,
time and seed, progress and cancel, then the segmentation preview and the precedence graph;
OK builds the parametric tree."""

import json
import os
import tempfile

from .qt import QtCore, QtGui, QtWidgets

from . import builder
from .fit_panel import PREVIEW_SIZE, FitPanel

RANGE_PRIMITIVES = ("box", "sphere", "cylinder", "cone", "torus")
RANGE_FILTER = ("Range images and point clouds (*.png *.npy *.ply *.xyz);;All files (*)")
RANGE_TYPES = (".png", ".npy", ".ply", ".xyz")
#: The sensor fields: (keyword of csgfit.fit_range, row title, tooltip).
SENSOR_FIELDS = (
    ("pixel_size", "Pixel size", "Orthographic: model units per pixel"),
    ("fx", "Focal length fx", "Pinhole: focal length in pixels along x"),
    ("fy", "Focal length fy", "Pinhole: focal length in pixels along y"),
    ("cx", "Principal point cx", "Pixels; 'image centre' when not given"),
    ("cy", "Principal point cy", "Pixels; 'image centre' when not given"),
    ("depth_unit", "Depth unit", "Model units per 16-bit PNG step"),
)
PROJECTION_FIELDS = {"orthographic": ("pixel_size",), "pinhole": ("fx", "fy")}


def split_paths(text):
    """The paths of the file row: separated by ';' (as the multi-file browser writes them)."""
    return [p.strip() for p in text.split(";") if p.strip()]


def read_sidecar(path):
    """The JSON sidecar next to a range image (same name, .json) as a dict, or None when there
    is none; ValueError when it is not JSON. The solver checks its fields when it reads it."""
    side = os.path.splitext(path)[0] + ".json"
    if not os.path.isfile(side):
        return None
    with open(side, encoding="utf-8") as f:
        try:
            d = json.load(f)
        except json.JSONDecodeError as e:
            raise ValueError(f"{os.path.basename(side)}: not JSON ({e.msg})") from None
    if not isinstance(d, dict):
        raise ValueError(f"{os.path.basename(side)}: not a JSON object")
    if "projection" not in d:  # the solver infers it the same way
        d["projection"] = "pinhole" if "fx" in d and "pixel_size" not in d else "orthographic"
    return d


class RangeToCsgPanel(FitPanel):
    """Task panel: range files, sensor fields (sidecar or typed), time, seed, primitives,
    Fit / Cancel, progress; after the fit the segmentation / depth-error preview and the
    precedence graph; OK builds the tree."""

    TITLE = "Range image to CSG"
    ICON = "csgfit_range_to_csg"
    START_TEXT = "Choose range images (one part, one or more views), then Fit."
    FILE_PLACEHOLDER = "range images or point clouds (PNG, NPY, PLY, XYZ; ';' between views)"
    BROWSE_TITLE = "Range images or point clouds of one part"
    FILE_FILTER = RANGE_FILTER

    def __init__(self, paths=None):
        self.sidecar = None
        self.edited = set()  # sensor fields the user changed: they override the sidecar
        self._preview_file = None
        if isinstance(paths, (list, tuple)):
            paths = "; ".join(paths)
        super().__init__(paths)

    # ---- the form -----------------------------------------------------------------------

    def _add_settings(self, grid):
        self.sensor_note = QtWidgets.QLabel("")
        self.sensor_note.setWordWrap(True)
        grid.addRow("Sensor", self.sensor_note)
        self.projection = QtWidgets.QComboBox()
        self.projection.addItems(list(PROJECTION_FIELDS))
        self.projection.currentTextChanged.connect(self._projection_changed)
        grid.addRow("Projection", self.projection)
        self.sensor = {}
        for name, title, tip in SENSOR_FIELDS:
            box = QtWidgets.QDoubleSpinBox()
            box.setDecimals(10)
            centre = name in ("cx", "cy")
            box.setRange(-1.0 if centre else 0.0, 1e6)
            box.setSpecialValueText("image centre" if centre else "not given")
            box.setValue(box.minimum())
            box.setToolTip(tip)
            box.valueChanged.connect(lambda _v, n=name: self.edited.add(n))
            grid.addRow(title, box)
            self.sensor[name] = box
        self.time = QtWidgets.QDoubleSpinBox()
        self.time.setRange(0.5, 3600)
        self.time.setValue(20)
        self.time.setSuffix(" s")
        grid.addRow("Time budget", self.time)
        grid.addRow("Primitives", self._primitive_boxes(
            [(name, True, name != "box") for name in RANGE_PRIMITIVES]))
        self.seed = QtWidgets.QSpinBox()
        self.seed.setRange(0, 2 ** 31 - 1)
        self.seed.setValue(1)
        grid.addRow("Seed", self.seed)
        self._projection_changed(self.projection.currentText(), user=False)
        self.edited = set()  # setting the fields' initial values is not an edit

    def _add_views(self, layout):
        self.preview = QtWidgets.QLabel()
        self.preview.setAlignment(QtCore.Qt.AlignCenter)
        self.preview.setMinimumSize(PREVIEW_SIZE, 120)
        self.preview.setToolTip("Left: the first view coloured by surface patch; right: the "
                                "tree's depth error as that sensor sees it")
        layout.addWidget(self.preview)
        legend = QtWidgets.QLabel("<small>left: patches (grey: none) &nbsp; right: depth error, "
                                  "white 0 to <span style='color:#dc2828'>red 1 %</span>, "
                                  "<span style='color:#285ae6'>blue: tree only</span></small>")
        legend.setAlignment(QtCore.Qt.AlignCenter)
        legend.setWordWrap(True)
        layout.addWidget(legend)
        self.report_text = QtWidgets.QPlainTextEdit()
        self.report_text.setReadOnly(True)
        self.report_text.setPlaceholderText("The precedence graph appears here after the fit.")
        self.report_text.setFont(QtGui.QFontDatabase.systemFont(QtGui.QFontDatabase.FixedFont))
        self.report_text.setMaximumHeight(180)
        layout.addWidget(self.report_text)
        layout.addStretch(1)

    def _projection_changed(self, projection, user=True):
        if user:
            self.edited.add("projection")
        for name in ("pixel_size", "fx", "fy"):
            self.sensor[name].setEnabled(name in PROJECTION_FIELDS[projection])

    def _browse(self):
        paths, _ = QtWidgets.QFileDialog.getOpenFileNames(self.form, self.BROWSE_TITLE, "",
                                                          self.FILE_FILTER)
        if paths:
            self.set_file("; ".join(paths))

    # ---- inputs -------------------------------------------------------------------------

    def paths(self):
        return split_paths(self.file_edit.text())

    def _input_changed(self, *_):
        self.result = None
        self._clear_views()
        paths = self.paths()
        if not paths:
            return
        for p in paths:
            if not os.path.isfile(p):
                self.show_error(f"cannot open '{p}': no such file")
                return
            if os.path.splitext(p)[1].lower() not in RANGE_TYPES:
                self.show_error(f"unknown input format '{p}' (expected .png, .npy, .ply or .xyz)")
                return
        try:
            self.show_sidecar(read_sidecar(paths[0]))
        except (OSError, ValueError) as e:
            self.show_error(str(e))
            return
        views = f"{len(paths)} views" if len(paths) > 1 else os.path.basename(paths[0])
        self.show_status(f"{views}: Fit when ready.")

    def show_sidecar(self, sidecar):
        """Fills the sensor fields from a sidecar dict (None: clears them, to be typed)."""
        self.sidecar = sidecar
        widgets = [self.projection] + list(self.sensor.values())
        for w in widgets:
            w.blockSignals(True)
        try:
            projection = (sidecar or {}).get("projection", "orthographic")
            if projection in PROJECTION_FIELDS:
                self.projection.setCurrentText(projection)
            for name, box in self.sensor.items():
                v = (sidecar or {}).get(name)
                box.setValue(float(v) if isinstance(v, (int, float)) else box.minimum())
        finally:
            for w in widgets:
                w.blockSignals(False)
        self._projection_changed(self.projection.currentText(), user=False)
        self.edited = set()
        first = os.path.basename(self.paths()[0]) if self.paths() else ""
        self.sensor_note.setText(
            f"from {os.path.splitext(first)[0]}.json (edit a field to override it)" if sidecar
            else "no sidecar: give pixel size (orthographic) or fx and fy (pinhole) for images")

    def intrinsics(self):
        """The fit_range intrinsics: without a sidecar every field given; with one, only the
        fields the user changed (all of the projection's when the projection changed)."""
        projection = self.projection.currentText()
        names = list(PROJECTION_FIELDS[projection]) + ["cx", "cy", "depth_unit"]
        out = {}
        for name in names:
            box = self.sensor[name]
            if box.value() == box.minimum():
                continue
            override = (self.sidecar is None or name in self.edited
                        or ("projection" in self.edited and name in PROJECTION_FIELDS[projection]))
            if override:
                out[name] = box.value()
        return out

    def options(self):
        """The fit_range keyword arguments the form describes."""
        return dict(self.intrinsics(), time=self.time.value(), seed=self.seed.value(),
                    primitives=[n for n, cb in self.primitive_checks.items() if cb.isChecked()])

    def source_name(self):
        paths = self.paths()
        return os.path.splitext(os.path.basename(paths[0]))[0] if paths else ""

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        paths = self.paths()
        if not paths:
            self.show_error("Choose one or more range images first.")
            return None
        return self.csgfit.fit_range, paths, self.options()

    def _fit_started(self):
        self._clear_views()

    def _show_progress(self, job):
        p = job.progress
        if p is None:
            super()._show_progress(job)
            return
        self.progress_bar.setValue(int(1000 * min(1.0, max(0.0, p.fraction))))
        stage = "surface patches" if p.fraction < 0.4 else "precedence graph and refinement"
        self.show_status(f"Fitting... {p.seconds:.1f} s ({stage})")

    def _fit_finished(self, result):
        g = result.precedence_graph
        errors = "; ".join(f"{os.path.basename(v.source)}: depth error {v.depth_error:.3g}"
                           for v in result.views)
        self.show_status(f"{result.stats.primitives} primitives in {g.subobjects} subobjects "
                         f"from {len(result.patches)} surface patches; silhouette IoU "
                         f"{result.stats.iou:.4f}" + (f"; {errors}" if errors else "")
                         + f"; {result.stats.seconds:.1f} s ({result.stats.stop_reason}).")
        self.report_text.setPlainText(result.report())
        if result.has_preview:
            fd, self._preview_file = tempfile.mkstemp(prefix="csgfit-range-", suffix=".png")
            os.close(fd)
            result.save_preview(self._preview_file)
            pix = QtGui.QPixmap(self._preview_file)
            self.preview.setPixmap(pix.scaled(2 * PREVIEW_SIZE, PREVIEW_SIZE,
                                              QtCore.Qt.KeepAspectRatio,
                                              QtCore.Qt.SmoothTransformation))
        else:
            self.preview.setText("(no preview: the first input has no camera)")

    def _clear_views(self):
        self.preview.clear()
        self.report_text.clear()
        if self._preview_file:
            try:
                os.unlink(self._preview_file)
            except OSError:
                pass
            self._preview_file = None

    # ---- OK / Cancel --------------------------------------------------------------------

    def build_tree(self, doc):
        return builder.build(doc, self.result, label=self.source_name() or None)

    def _close(self):
        self._clear_views()
