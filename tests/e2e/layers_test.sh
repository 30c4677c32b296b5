#!/bin/bash
# The solver's stages include only themselves and earlier stages (scripts/check_layers.py).
# Usage: bash layers_test.sh <path-to-csgfit-cli> <source-dir>
set -u
src=${2:?usage: layers_test.sh CLI SOURCE_DIR}
exec /usr/bin/python3 "$src/scripts/check_layers.py"
