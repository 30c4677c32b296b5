// Errors the user can act on.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace csgfit {

/// `text` made safe to show on a terminal as one line: control bytes, invalid UTF-8 and the
/// Unicode controls that reorder or hide text become '?', and anything past `max_chars` bytes
/// is cut to "...". Messages quote paths and file content; neither may recolour a terminal.
inline std::string printable_message(const std::string& text, std::size_t max_chars = 400) {
  std::string out;
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n && out.size() < max_chars;) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      out += (c >= 0x20 && c != 0x7f) ? static_cast<char>(c) : '?';
      ++i;
      continue;
    }
    // A well-formed 2..4 byte sequence, then its code point.
    const std::size_t len = c >= 0xf0 && c < 0xf5 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
    bool ok = len > 0 && i + len <= n;
    char32_t cp = ok ? (c & (0x7f >> len)) : 0;
    for (std::size_t k = 1; ok && k < len; ++k) {
      const unsigned char d = static_cast<unsigned char>(text[i + k]);
      ok = (d & 0xc0) == 0x80;
      cp = (cp << 6) | (d & 0x3f);
    }
    ok = ok && !(len == 3 && cp < 0x800) && !(len == 4 && (cp < 0x10000 || cp > 0x10ffff)) &&
         !(cp >= 0xd800 && cp <= 0xdfff) && !(cp >= 0x80 && cp <= 0x9f) &&
         !(cp >= 0x200b && cp <= 0x200f) && !(cp >= 0x202a && cp <= 0x202e) &&
         !(cp >= 0x2066 && cp <= 0x2069) && cp != 0xfeff;
    if (ok) {
      out.append(text, i, len);
      i += len;
    } else {
      out += '?';
      ++i;
    }
  }
  if (out.size() >= max_chars && out.size() < n) out += "...";
  return out;
}

/// Bad input or options: the message is one line that names the problem (and the file), meant
/// to be shown to the user as it is (made printable and cut short here, whatever it quotes).
/// The CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(printable_message(message)) {}
  explicit InputError(const char* message) : InputError(std::string(message)) {}
};

}  // namespace csgfit
