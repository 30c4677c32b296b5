"""The csgfit module the tests beside this file test: the one in $CSGFIT_BUILD_DIR/python
(default: <repo>/build/python). Importing this skips the importing test file, with the reason,
when the module has not been built (-DCSGFIT_BUILD_PYTHON=ON)."""

import os
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("CSGFIT_BUILD_DIR", os.path.join(REPO, "build"))
#: ../shared/benchmarks beside the checkout.
BENCHMARKS = os.path.join(os.path.dirname(REPO), "shared", "benchmarks")

sys.path.insert(0, os.path.join(BUILD, "python"))
csgfit = pytest.importorskip(
    "csgfit", reason=f"csgfit module not built in {BUILD}/python; configure with "
    "-DCSGFIT_BUILD_PYTHON=ON or set CSGFIT_BUILD_DIR")
