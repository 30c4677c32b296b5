# CSG Fit workbench, non-GUI part (run by FreeCAD and freecadcmd at start-up).
# Nothing to register: scripts use `from csgfit_freecad import builder` (this folder is on
# sys.path once FreeCAD has scanned its Mod folders).
