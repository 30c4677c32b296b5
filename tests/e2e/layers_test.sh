#!/bin/bash
# The solver's stages include only themselves and earlier stages (scripts/check_layers.py).
# Usage: bash layers_test.sh <path-to-csgfit-cli> <source-dir>
set -u
. "$(dirname "$0")/lib.sh"
e2e_args 2 "$@"
exec "$PY" "$SRC/scripts/check_layers.py"
