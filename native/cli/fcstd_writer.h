// .FCStd output: FreeCAD documents are written by FreeCAD itself.
#pragma once

#include <string>

namespace csgfit::cli {

/// Writes the csgfit JSON document `json_text` (2D or 3D) to `out` as a FreeCAD document, by
/// running freecadcmd on the workbench's writer script (CSGFIT_FCSTD_WRITER overrides its
/// path). Throws InputError with a one-line reason when FreeCAD is missing or fails.
void write_fcstd(const std::string& json_text, const std::string& out);

}  // namespace csgfit::cli
