// Files: whole-file reads and atomic writes, so that no output is ever left half-written.
#pragma once

#include <string>

namespace csgfit {

/// Writes `contents` to `path` through a temporary file in the same folder and a rename, so
/// that a failed or interrupted write never leaves a partial file. Throws InputError.
void write_file_atomic(const std::string& path, const std::string& contents);

}  // namespace csgfit
