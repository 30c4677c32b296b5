"""The "Image to CSG" task panel: a bitmap file, its threshold and model frame, the search
settings, the fit's preview and a choice among the best tree and its alternatives."""

import os

from .qt import QtWidgets

from . import builder
from .fit_panel import FitPanel

PRIMITIVES = ("rectangle", "circle", "ellipse", "triangle")
QUALITIES = ("fast", "default", "best", "paper")
IMAGE_FILTER = "Images (*.png *.jpg *.jpeg *.bmp *.pgm *.pbm *.ppm *.tga);;All files (*)"


def add_model_frame_rows(panel, grid):
    """Pixel size and Thickness (0 = auto, 10 pixels): how pixels become millimetres, for every
    panel that fits bitmaps."""
    panel.pixel_size = QtWidgets.QDoubleSpinBox()
    panel.pixel_size.setRange(1e-4, 1e4)
    panel.pixel_size.setDecimals(4)
    panel.pixel_size.setValue(1.0)
    panel.pixel_size.setSuffix(" mm")
    grid.addRow("Pixel size", panel.pixel_size)
    panel.thickness = QtWidgets.QDoubleSpinBox()
    panel.thickness.setRange(0, 1e5)
    panel.thickness.setDecimals(3)
    panel.thickness.setSpecialValueText("auto (10 pixels)")
    panel.thickness.setSuffix(" mm")
    grid.addRow("Thickness", panel.thickness)


class ImageToCsgPanel(FitPanel):
    """Task panel: settings, Fit / Cancel, progress, preview, tree choice; OK builds the tree."""

    TITLE = "Image to CSG"
    ICON = "csgfit_image_to_csg"
    START_TEXT = "Choose a bitmap, then Fit."
    BROWSE_TITLE = "Bitmap to fit"
    FILE_FILTER = IMAGE_FILTER

    FILE_PLACEHOLDER = "bitmap file (PNG, JPEG, BMP, PGM, TGA)"

    def __init__(self, path=None):
        self.target = None
        super().__init__(path)

    # ---- form ---------------------------------------------------------------------------

    def _add_settings(self, grid):
        self._add_bitmap_rows(grid)
        self._add_search_rows(
            grid, 10, 0.1, (QUALITIES, "default", "How hard the search tries"), 1e6,
            "Penalty per primitive: higher gives smaller trees",
            [(name, True, True) for name in PRIMITIVES])
        self.alternatives = QtWidgets.QSpinBox()
        self.alternatives.setRange(0, 10)
        self.alternatives.setValue(2)
        grid.addRow("Alternatives", self.alternatives)

    def _add_views(self, layout):
        self.tree_choice = QtWidgets.QComboBox()
        self.tree_choice.setEnabled(False)
        self.tree_choice.currentIndexChanged.connect(self._show_preview)
        layout.addWidget(self.tree_choice)
        self._add_preview(layout, "Grey: matched; red: result only; blue: image only")

    def _add_bitmap_rows(self, grid):
        """Threshold, Invert, Pixel size, Thickness: how the file becomes a model-unit shape."""
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
        add_model_frame_rows(self, grid)

    # ---- inputs -------------------------------------------------------------------------

    def options(self):
        """The fit_image keyword arguments the form describes."""
        return dict(self.search_options(),
                    threshold=None if self.threshold.value() < 0 else self.threshold.value(),
                    invert=self.invert.isChecked(), pixel_size=self.pixel_size.value(),
                    thickness=self.thickness.value(), quality=self.quality.currentText(),
                    alternatives=self.alternatives.value())

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
        self.show_overlay(self.target, None)

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
        self.show_overlay(self.target,
                          self.result.raster() if i < 0 else self.result.alternatives[i].raster())

    # ---- OK -----------------------------------------------------------------------------

    def build_tree(self, doc):
        """The chosen tree, extruded to the form's thickness (its own when auto)."""
        name = os.path.splitext(os.path.basename(self.file_edit.text().strip()))[0]
        return builder.build(doc, self.result, thickness=self.thickness.value() or None,
                             label=name or None, alternative=self.chosen_alternative())
