# CSG Fit workbench, GUI part. FreeCAD 0.20 executes this file without __file__ and with
# module-level names invisible to the class methods, so everything is imported where used.


class CSGFitWorkbench(Gui.Workbench):  # noqa: F821 (Gui is provided by FreeCAD)
    """Fit compact CSG trees to bitmaps, meshes and range images and build them as parametric
    Part trees."""

    MenuText = "CSG Fit"
    ToolTip = ("Turn bitmaps, meshes and range images into compact, editable CSG trees of "
               "Part primitives")

    def __init__(self):
        import csgfit_freecad
        self.__class__.Icon = csgfit_freecad.icon("csgfit_workbench")

    def Initialize(self):
        from csgfit_freecad import commands
        commands.register()
        self.appendToolbar("CSG Fit", commands.COMMANDS)
        self.appendMenu("CSG Fit", commands.COMMANDS)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(CSGFitWorkbench())  # noqa: F821
