"""The CSG Fit FreeCAD workbench: builder (headless), FCStd writer, GUI commands and task panel.

The builder and the FCStd writer need only FreeCAD; fitting needs the native `csgfit` module,
found by import_csgfit().
"""

import os
import sys

#: The repository this package lives in (the workbench is installed as a symlink to it).
PACKAGE_DIR = os.path.dirname(os.path.realpath(__file__))
REPO_DIR = os.path.dirname(os.path.dirname(PACKAGE_DIR))
ICONS_DIR = os.path.join(REPO_DIR, "icons")


def icon(name: str) -> str:
    """Path of an SVG icon of the workbench."""
    return os.path.join(ICONS_DIR, name + ".svg")


def build_python_dirs():
    """Where the built `csgfit` package may be, in order: $CSGFIT_BUILD_DIR/python, then the
    repository's build/python."""
    dirs = []
    env = os.environ.get("CSGFIT_BUILD_DIR")
    if env:
        dirs.append(os.path.join(env, "python"))
    dirs.append(os.path.join(REPO_DIR, "build", "python"))
    return dirs


def import_csgfit():
    """Imports the native csgfit package, adding the build folder to sys.path if needed.

    Raises ImportError with the places searched when it is not built.
    """
    try:
        import csgfit  # noqa: F401  (already on the path, e.g. installed)
        return csgfit
    except ImportError:
        pass
    for d in build_python_dirs():
        if os.path.isfile(os.path.join(d, "csgfit", "__init__.py")):
            if d not in sys.path:
                sys.path.insert(0, d)
            import csgfit
            return csgfit
    raise ImportError("the csgfit Python module is not built (looked in "
                      + ", ".join(build_python_dirs())
                      + "); build with -DCSGFIT_BUILD_PYTHON=ON or set CSGFIT_BUILD_DIR")
