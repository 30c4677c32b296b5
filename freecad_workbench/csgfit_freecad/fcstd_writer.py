"""Writes a csgfit result (JSON) as a FreeCAD document (.FCStd), headless. A morph document
(one with a "morph" key) is built by morph_builder.build_morph.

Run with FreeCAD's own interpreter; arguments come from the environment because freecadcmd
treats its command-line arguments as files to open:

    CSGFIT_JSON=in.json CSGFIT_FCSTD=out.FCStd [CSGFIT_THICKNESS=mm] [CSGFIT_LABEL=name] \
        freecadcmd <repo>/freecad_workbench/csgfit_freecad/fcstd_writer.py

It also runs under /usr/bin/python3 (FreeCAD's lib is added to sys.path). The document is
saved to a temporary file next to the output and renamed, so a failure never leaves a partial
.FCStd. Exit status 0 on success; on failure one line "csgfit: error: ..." on stderr and
status 2 (bad input) or 1 (FreeCAD failed).
"""

import os
import shutil
import sys
import tempfile

FREECAD_LIB = "/usr/lib/freecad-python3/lib"


def _fail(message, status):
    sys.stderr.write(f"csgfit: error: {message}\n")
    sys.stderr.flush()
    # freecadcmd ignores SystemExit codes from scripts; _exit keeps the status.
    os._exit(status)


def write_fcstd(json_path, fcstd_path, thickness=None, label=None, doc_name=None):
    """Builds the tree of `json_path` into a new document (named `doc_name`, else after
    `fcstd_path`) and saves it atomically as `fcstd_path`. Returns the BuildResult's root volume. Raises builder.BuildError on bad
    input, RuntimeError when the tree does not recompute to a valid solid."""
    import FreeCAD as App

    from csgfit_freecad import builder, morph_builder

    result = builder.load_result(json_path)
    # A morph document (csgfit morph) becomes one tree driven by its sheet's `morph` cell.
    build = morph_builder.build_morph if morph_builder.is_morph(result) else builder.build
    name = doc_name or os.path.splitext(os.path.basename(fcstd_path))[0] or "csgfit"
    doc_name = "".join(c if c.isalnum() else "_" for c in name)
    doc = App.newDocument(doc_name)
    try:
        built = build(doc, result, thickness=thickness, label=label)
        problems = builder.check_tree(doc, built.group)
        if problems:
            raise RuntimeError("the FreeCAD tree is not valid: " + "; ".join(problems))
        out_dir = os.path.dirname(os.path.abspath(fcstd_path))
        # A fresh folder rather than a temporary file: FreeCAD keeps a backup copy
        # (".FCStd1") when it saves over an existing file.
        tmp_dir = tempfile.mkdtemp(prefix=".csgfit-", dir=out_dir)
        # Saved under the document's own name: FreeCAD labels the document after the file.
        tmp = os.path.join(tmp_dir, name + os.path.splitext(fcstd_path)[1])
        try:
            doc.saveAs(tmp)
            os.replace(tmp, fcstd_path)
        finally:
            shutil.rmtree(tmp_dir, ignore_errors=True)
        return built.root.Shape.Volume
    finally:
        App.closeDocument(doc.Name)


def main():
    json_path = os.environ.get("CSGFIT_JSON")
    fcstd_path = os.environ.get("CSGFIT_FCSTD")
    if not json_path or not fcstd_path:
        _fail("set CSGFIT_JSON=<in.json> and CSGFIT_FCSTD=<out.FCStd>", 2)
    thickness = os.environ.get("CSGFIT_THICKNESS") or None
    if thickness is not None:
        try:
            thickness = float(thickness)
        except ValueError:
            _fail(f"CSGFIT_THICKNESS is not a number: {thickness}", 2)
    label = os.environ.get("CSGFIT_LABEL") or None
    # The CLI saves to a temporary file first; the document keeps the name of the real one.
    doc_name = os.environ.get("CSGFIT_DOC_NAME") or None

    pkg_parent = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
    if pkg_parent not in sys.path:
        sys.path.insert(0, pkg_parent)
    if FREECAD_LIB not in sys.path and os.path.isdir(FREECAD_LIB):
        sys.path.append(FREECAD_LIB)
    try:
        import FreeCAD  # noqa: F401
    except ImportError as e:
        _fail(f"FreeCAD's Python API is not available ({e})", 1)
    from csgfit_freecad import builder

    try:
        write_fcstd(json_path, fcstd_path, thickness=thickness, label=label, doc_name=doc_name)
    except builder.BuildError as e:
        _fail(str(e).splitlines()[0], 2)
    except Exception as e:  # FreeCAD raises its own exception types
        _fail(f"writing {fcstd_path}: {str(e).splitlines()[0] if str(e) else type(e).__name__}",
              1)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


def _run_as_script():
    # python sets __name__ to "__main__"; freecadcmd runs a script file with __name__ set to
    # the file's stem and sys.argv[0] set to its path. An import does neither.
    return __name__ == "__main__" or (
        bool(sys.argv) and os.path.realpath(sys.argv[0]) == os.path.realpath(__file__))


if _run_as_script():
    main()
