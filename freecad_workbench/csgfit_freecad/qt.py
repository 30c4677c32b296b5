"""Qt for the workbench, through FreeCAD's PySide shim, so that one workbench loads on FreeCAD
0.20 (Qt 5, PySide2) and on FreeCAD 1.x (Qt 6, PySide6, no PySide2).

The shim always has QtCore and QtGui; FreeCAD 1.x adds QtWidgets, and on 0.20 its QtGui carries
the widget classes as Qt 4 did."""

from PySide import QtCore, QtGui  # noqa: F401

try:
    from PySide import QtWidgets
except ImportError:  # FreeCAD 0.20
    QtWidgets = QtGui
