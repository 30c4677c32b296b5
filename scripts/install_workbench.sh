#!/usr/bin/env bash
# Installs the CSG Fit workbench for the current user's FreeCAD (0.20 on Debian finds it in
# the GUI and in freecadcmd): links <user app data>/Mod/CSGFit to this checkout's
# freecad_workbench/, so the workbench always runs the checkout's code. Idempotent.
# The workbench finds the Python module in $CSGFIT_BUILD_DIR/python or <repo>/build/python.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
src="$repo/freecad_workbench"

# FreeCAD decides where user modules live (~/.local/share/FreeCAD or a legacy ~/.FreeCAD).
user_dir=""
if command -v freecadcmd >/dev/null 2>&1; then
  user_dir="$(freecadcmd -c 'import FreeCAD; print("CSGFIT_DIR=" + FreeCAD.getUserAppDataDir())' \
    2>/dev/null | sed -n 's/^CSGFIT_DIR=//p' | tail -n 1 || true)"
fi
if [ -z "$user_dir" ]; then
  user_dir="${XDG_DATA_HOME:-$HOME/.local/share}/FreeCAD/"
fi
mod_dir="${user_dir%/}/Mod"
dest="$mod_dir/CSGFit"

mkdir -p "$mod_dir"
if [ -L "$dest" ]; then
  rm -f "$dest"
elif [ -e "$dest" ]; then
  echo "install_workbench: $dest exists and is not a link; remove it first" >&2
  exit 1
fi
ln -s "$src" "$dest"
echo "CSG Fit workbench: $dest -> $src"
