"""The "Morph two images" task panel: bitmaps A and B, the pair search's settings (time,
preset, turn direction, seed) and the model frame; OK builds one parametric tree whose
parameter sheet's `morph` cell moves it from shape A (0) to shape B (1)."""

import os

from .qt import QtWidgets

from . import morph_builder
from .fit_panel import FitPanel
from .image_panel import IMAGE_FILTER, add_model_frame_rows

PRESETS = ("default", "paper")
ROTATIONS = ("shortest", "cw", "ccw")


class MorphPanel(FitPanel):
    """Task panel: image A (the file row), image B, settings, Fit / Cancel fit, progress,
    the thresholded bitmap A; OK builds the morph tree (morph_builder.build_morph)."""

    TITLE = "Morph two images"
    ICON = "csgfit_morph_images"
    START_TEXT = "Choose images A and B (same size), then Fit."
    FILE_PLACEHOLDER = "image A (morph = 0)"
    BROWSE_TITLE = "Image A"
    FILE_FILTER = IMAGE_FILTER

    # ---- form ---------------------------------------------------------------------------

    def _add_settings(self, grid):
        grid.addRow("Image B", self._image_b_row())
        self._add_time_row(grid, 20, 0.1)
        self.preset = self._choice(PRESETS, "paper: the parameters of Gibson et al., Table 2")
        grid.addRow("Preset", self.preset)
        self.rotate = self._choice(ROTATIONS, "Which way a primitive turns from A to B")
        grid.addRow("Rotate", self.rotate)
        self._add_seed_row(grid)
        add_model_frame_rows(self, grid)

    def _image_b_row(self):
        row = QtWidgets.QWidget()
        layout = QtWidgets.QHBoxLayout(row)
        layout.setContentsMargins(0, 0, 0, 0)
        self.file_b_edit = QtWidgets.QLineEdit()
        self.file_b_edit.setPlaceholderText("image B (morph = 1)")
        self.file_b_edit.editingFinished.connect(self._input_changed)
        browse = QtWidgets.QPushButton("Browse...")
        browse.clicked.connect(self._browse_b)
        layout.addWidget(self.file_b_edit)
        layout.addWidget(browse)
        return row

    @staticmethod
    def _choice(items, tip):
        box = QtWidgets.QComboBox()
        box.addItems(list(items))
        box.setToolTip(tip)
        return box

    def _browse_b(self):
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self.form, "Image B",
                                                        self.file_b_edit.text(), IMAGE_FILTER)
        if path:
            self.set_file_b(path)

    def set_file_b(self, path):
        """Morph to this file."""
        self.file_b_edit.setText(path)
        self._input_changed()

    def _add_views(self, layout):
        self._add_preview(layout, "Bitmap A as it will be fitted")

    # ---- inputs -------------------------------------------------------------------------

    def paths(self):
        return self.file_edit.text().strip(), self.file_b_edit.text().strip()

    def options(self):
        """The csgfit.morph keyword arguments the form describes."""
        return {"time": self.time.value(), "seed": self.seed.value(),
                "preset": self.preset.currentText(), "rotate": self.rotate.currentText(),
                "pixel_size": self.pixel_size.value(), "thickness": self.thickness.value()}

    def _input_changed(self, *_):
        """Shows bitmap A thresholded, so the user sees what will be fitted."""
        self.result = None
        path = self.paths()[0]
        if not path or self.csgfit is None:
            return
        try:
            target = self.csgfit.load_bitmap(path)
        except ValueError as e:
            self.preview.clear()
            self.show_error(str(e))
            return
        h, w = target.shape
        self.show_status(f"{os.path.basename(path)}: {w} x {h} pixels.")
        self.show_overlay(target, None)

    # ---- fitting ------------------------------------------------------------------------

    def fit_request(self):
        path_a, path_b = self.paths()
        if not path_a:
            self.show_error("Choose image A first.")
            return None
        if not path_b:
            self.show_error("Choose image B first.")
            return None
        if not hasattr(self.csgfit, "morph"):
            self.show_error("This build of the csgfit module has no morph(); rebuild it.")
            return None
        csgfit = self.csgfit

        # FitJob calls fit(source, progress=..., cancel=..., **options); B rides along here.
        def morph(a, **kw):
            return csgfit.morph(a, path_b, **kw)

        return morph, path_a, self.options()

    def summary(self, result):
        doc = morph_builder.load_morph(result)
        a, b = doc.get("stats") or {}, doc["morph"].get("stats_b") or {}
        return (f"IoU A {float(a.get('iou') or 0):.4f}, B {float(b.get('iou') or 0):.4f}, "
                f"{len(morph_builder.paired_leaves(doc['tree'], doc['morph']['tree_b']))} "
                f"primitives, {float(a.get('seconds') or 0):.1f} s. "
                "OK builds the tree; its sheet's 'morph' cell goes from A (0) to B (1).")

    def _fit_finished(self, result):
        """Nothing more to show: the status line has both trees' IoU."""

    # ---- OK -----------------------------------------------------------------------------

    def build_tree(self, doc):
        """The morph tree, extruded to the form's thickness (the result's own when auto)."""
        name = os.path.splitext(os.path.basename(self.paths()[0]))[0]
        return morph_builder.build_morph(doc, self.result,
                                         thickness=self.thickness.value() or None,
                                         label=(name + " morph") if name else None)
