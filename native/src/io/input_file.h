// Whole-file reads under a size limit, and the one-line messages every reader throws.
#pragma once

#include <cstddef>
#include <string>

namespace csgfit::io_detail {

/// The path as messages name it: in single quotes.
inline std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// Throws InputError(message): the one-line error the command line prints as it is.
[[noreturn]] void fail(const std::string& message);

/// `n` and `noun`, with an "s" unless n is 1 (messages only).
std::string count_text(std::size_t n, const char* noun);

/// The extension of `path` after its last dot, lower-case; empty when the last path component
/// has no dot.
std::string lower_extension(const std::string& path);

/// What a reader expects: any bytes, or text (which has no NUL byte).
enum class FileContent { Binary, Text };

/// The whole file. Refuses a missing or unreadable file, a directory, a device (it might never
/// end; pipes are read), and an empty file; a file larger than `max_bytes` is refused before it
/// is read ("... is larger than N bytes, " + limit_reason) or, for a pipe, as soon as it grows
/// past the limit. The string keeps a NUL after the last byte, which no parser relies on but
/// which makes a strtod-style overrun impossible. The file's size is checked against the memory
/// budget first; for FileContent::Text a NUL byte is refused where it is met, so that a sparse
/// or binary file given as text is not read to its end.
std::string read_whole_file(const std::string& path, long long max_bytes, const char* limit_reason,
                            FileContent content = FileContent::Binary);

}  // namespace csgfit::io_detail
