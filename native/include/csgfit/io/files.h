// Files: atomic writes, and one batch per command so that its outputs land together or not at
// all; no output is ever left half-written, and none is kept when a later one failed.
#pragma once

#include <string>

namespace csgfit {

/// Writes `contents` to `path` through a temporary file in the same folder and a rename, so
/// that a failed or interrupted write never leaves a partial file. Inside an OutputBatch the
/// rename waits for the batch's commit. Throws InputError.
void write_file_atomic(const std::string& path, const std::string& contents);

/// A fresh, empty temporary file in the folder of `path` (created with O_EXCL, mode 0666 less
/// the umask), for writers that write by file name (OpenCASCADE, FreeCAD). Its name ends with
/// `path`'s extension. Throws InputError naming `path` when the folder takes no new file.
std::string make_temp_beside(const std::string& path);

/// Moves the finished temporary file `temp` onto `path`: now, or at the open batch's commit.
/// Throws InputError (and removes `temp`) when the rename fails.
void publish_file(const std::string& temp, const std::string& path);

/// Throws InputError unless `path` can be created: its folder exists and takes a new file (a
/// temporary one is made and removed), and `path` is not itself a folder.
void check_writable(const std::string& path);

/// While one is alive, the files written through write_file_atomic and publish_file wait under
/// their temporary names; commit() renames them all, and a batch destroyed without commit (the
/// command failed) removes them. One batch at a time per process.
class OutputBatch {
 public:
  OutputBatch();
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;
  /// Renames every waiting file onto its path; if one rename fails, the files already moved by
  /// this commit are removed too and InputError names the one that failed.
  void commit();
};

}  // namespace csgfit
