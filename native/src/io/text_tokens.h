// Scanning the text formats (ASCII STL, OBJ, OFF, ASCII PLY, the PLY and binvox headers):
// white-space separated tokens, lines, and locale-independent numbers. Inline because the
// readers call them once per token.
#pragma once

#include <cctype>
#include <charconv>
#include <cstddef>
#include <cstring>
#include <string_view>
#include <system_error>

namespace csgfit::io_detail {

/// A position in text, with the line number for messages.
struct Cursor {
  const char* p;
  const char* end;
  long long line = 1;

  bool at_end() const { return p >= end; }
};

/// White space other than a newline.
inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/// Skips spaces and newlines (counting lines).
inline void skip_space(Cursor& c) {
  while (c.p < c.end && (is_blank(*c.p) || *c.p == '\n')) {
    if (*c.p == '\n') ++c.line;
    ++c.p;
  }
}

/// The token after the blanks at the cursor, without crossing a newline (empty at the end of
/// the line or text).
inline std::string_view next_token_on_line(Cursor& c) {
  while (c.p < c.end && is_blank(*c.p)) ++c.p;
  const char* b = c.p;
  while (c.p < c.end && !is_blank(*c.p) && *c.p != '\n') ++c.p;
  return std::string_view(b, static_cast<std::size_t>(c.p - b));
}

/// Next whitespace-delimited token, across newlines (empty at the end of the text).
inline std::string_view next_token(Cursor& c) {
  skip_space(c);
  return next_token_on_line(c);
}

/// Moves past the next newline (or to the end).
inline void skip_line(Cursor& c) {
  while (c.p < c.end && *c.p != '\n') ++c.p;
  if (c.p < c.end) {
    ++c.p;
    ++c.line;
  }
}

/// The rest of the current line, its newline included, and moves past it.
inline std::string_view take_line(Cursor& c) {
  const char* b = c.p;
  skip_line(c);
  return std::string_view(b, static_cast<std::size_t>(c.p - b));
}

/// The first token of *s (empty when there is none); *s keeps what follows it.
inline std::string_view take_token(std::string_view* s) {
  std::size_t i = 0;
  while (i < s->size() && (is_blank((*s)[i]) || (*s)[i] == '\n')) ++i;
  std::size_t j = i;
  while (j < s->size() && !is_blank((*s)[j]) && (*s)[j] != '\n') ++j;
  const std::string_view t = s->substr(i, j - i);
  s->remove_prefix(j);
  return t;
}

/// Whether `a` equals the lower-case `b`, ignoring case.
inline bool equals_ci(std::string_view a, const char* b) {
  if (a.size() != std::strlen(b)) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  }
  return true;
}

/// A decimal floating-point number, the whole token; "nan"/"inf" parse, and the caller refuses
/// them with a message about non-finite values.
inline bool parse_double(std::string_view t, double* value) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

/// A signed integer prefix of t (e.g. the "12" of "12/4/7"); *rest receives what follows.
inline bool parse_int_prefix(std::string_view t, long long* value, std::string_view* rest) {
  const char* b = t.data();
  const char* e = t.data() + t.size();
  if (b < e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, *value);
  if (r.ec != std::errc()) return false;
  *rest = std::string_view(r.ptr, static_cast<std::size_t>(e - r.ptr));
  return true;
}

/// A non-negative decimal integer, the whole token.
inline bool parse_count(std::string_view t, unsigned long long* value) {
  if (t.empty() || t.front() == '-') return false;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *value);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

}  // namespace csgfit::io_detail
