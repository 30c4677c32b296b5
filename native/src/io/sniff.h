// What a file's content looks like, so that a reader can say "this is a PNG, not an STL mesh"
// instead of a parse error.
#pragma once

#include <cstddef>
#include <string>

namespace csgfit::io_detail {

/// Whether `d` starts with `prefix`.
bool starts_with(const std::string& d, const char* prefix);

/// Whether [p, end) starts with the lower-case `word`, ignoring case.
bool starts_with_ci(const char* p, const char* end, const char* word);

/// Whether the first `limit` bytes of `d` hold a NUL or a control character that text files do
/// not have.
bool has_binary_bytes(const std::string& d, std::size_t limit = std::string::npos);

/// What the content looks like ("a PNG image", "an OFF mesh", ...), from signatures that do not
/// occur at the start of the format named by the extension; empty when nothing is recognised.
std::string sniff(const std::string& d);

/// Throws "'path' looks like <what>, not <expected> (wrong file extension?)".
[[noreturn]] void fail_mislabelled(const std::string& path, const std::string& what,
                                   const std::string& expected);

}  // namespace csgfit::io_detail
