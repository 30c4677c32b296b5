// .csg tokens. Strings follow OpenSCAD's escapes, and also take what OpenSCAD 2021 writes for
// text(): the string as it is, unescaped, so a '"' inside it only ends it when a ',' ')' ']'
// ';' or '}' follows (see string_ends_at).

#include "io/openscad/csg_lexer.h"

#include <charconv>
#include <cstring>
#include <system_error>

#include "csgfit/error.h"

namespace csgfit::io_detail {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_name_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '$';
}
bool is_name_char(char c) { return is_name_start(c) || is_digit(c); }
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

int hex_digit(char c) {
  if (is_digit(c)) return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

void append_utf8(char32_t cp, std::string* out) {
  if (cp < 0x80) {
    *out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    *out += static_cast<char>(0xc0 | (cp >> 6));
    *out += static_cast<char>(0x80 | (cp & 0x3f));
  } else if (cp < 0x10000) {
    *out += static_cast<char>(0xe0 | (cp >> 12));
    *out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
    *out += static_cast<char>(0x80 | (cp & 0x3f));
  } else {
    *out += static_cast<char>(0xf0 | (cp >> 18));
    *out += static_cast<char>(0x80 | ((cp >> 12) & 0x3f));
    *out += static_cast<char>(0x80 | ((cp >> 6) & 0x3f));
    *out += static_cast<char>(0x80 | (cp & 0x3f));
  }
}

constexpr const char* kPunct = "(){}[],;=!#%*";

}  // namespace

void CsgLexer::fail(std::size_t line, const std::string& what) const {
  throw InputError(std::string(file_) + ":" + std::to_string(line) + ": " + what);
}

void CsgLexer::skip_space_and_comments() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (is_blank(c)) {
      ++pos_;
    } else if (c == '/' && peek(1) == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else if (c == '/' && peek(1) == '*') {
      const std::size_t opened = line_;
      const std::size_t close = text_.find("*/", pos_ + 2);
      if (close == std::string_view::npos) fail(opened, "a /* comment is never closed");
      for (std::size_t i = pos_; i < close; ++i) line_ += text_[i] == '\n';
      pos_ = close + 2;
    } else {
      return;
    }
  }
}

void CsgLexer::next(CsgToken* t) {
  skip_space_and_comments();
  t->offset = pos_;
  t->line = line_;
  if (pos_ >= text_.size()) {
    t->kind = CsgToken::Kind::End;
    t->text = {};
    return;
  }
  const char c = text_[pos_];
  const bool sign = (c == '-' || c == '+');
  if (is_digit(c) || (c == '.' && is_digit(peek(1))) ||
      (sign && (is_digit(peek(1)) || (peek(1) == '.' && is_digit(peek(2)))))) {
    lex_number(t);
  } else if (is_name_start(c) || (sign && is_name_start(peek(1)))) {
    const std::size_t b = pos_;
    pos_ += sign ? 2 : 1;
    while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
    t->kind = CsgToken::Kind::Name;
    t->text = text_.substr(b, pos_ - b);
    const std::string_view bare = sign ? t->text.substr(1) : t->text;
    if (bare == "inf" || bare == "nan") {
      fail(line_, "the number '" + std::string(t->text) +
                      "' is not finite (NaN or infinity in the .scad's arithmetic)");
    }
    if (sign) fail(line_, "unexpected '" + std::string(t->text) + "' (a sign before a name)");
  } else if (c == '"') {
    lex_string(t);
  } else if (std::strchr(kPunct, c) != nullptr) {
    t->kind = CsgToken::Kind::Punct;
    t->text = text_.substr(pos_++, 1);
  } else {
    fail(line_, "unexpected character '" + std::string(1, c) + "'");
  }
}

void CsgLexer::lex_number(CsgToken* t) {
  const std::size_t b = pos_;
  if (text_[pos_] == '-' || text_[pos_] == '+') ++pos_;
  while (is_digit(peek())) ++pos_;
  if (peek() == '.') {
    ++pos_;
    while (is_digit(peek())) ++pos_;
  }
  if ((peek() == 'e' || peek() == 'E') &&
      (is_digit(peek(1)) || ((peek(1) == '-' || peek(1) == '+') && is_digit(peek(2))))) {
    pos_ += 2;
    while (is_digit(peek())) ++pos_;
  }
  t->kind = CsgToken::Kind::Number;
  t->text = text_.substr(b, pos_ - b);
  if (is_name_char(peek()) || peek() == '.') {
    fail(line_, "bad number '" + std::string(text_.substr(b, pos_ - b + 1)) + "'");
  }
  // from_chars takes no '+', and would take "inf"; the span here is digits only.
  const char* first = text_.data() + b + (text_[b] == '+' ? 1 : 0);
  const auto r = std::from_chars(first, text_.data() + pos_, t->number);
  if (r.ec == std::errc::result_out_of_range) {
    fail(line_, "the number '" + std::string(t->text) + "' is out of the range of a double");
  }
  if (r.ec != std::errc() || r.ptr != text_.data() + pos_) {
    fail(line_, "bad number '" + std::string(t->text) + "'");
  }
}

// Whether the '"' at `quote` closes the string: OpenSCAD 2021 does not escape quotes in
// text(), and in a .csg a string is always followed by one of these.
bool CsgLexer::string_ends_at(std::size_t quote) const {
  std::size_t i = quote + 1;
  while (i < text_.size() && (is_blank(text_[i]) || text_[i] == '\n')) ++i;
  return i >= text_.size() || std::strchr(",)];}", text_[i]) != nullptr;
}

// Appends the escape at `backslash` to *out; returns the bytes it takes. Unknown escapes
// (OpenSCAD 2021 writes a text()'s backslashes as they are) stay as written.
std::size_t CsgLexer::decode_escape(std::size_t backslash, std::string* out) const {
  const char e = backslash + 1 < text_.size() ? text_[backslash + 1] : '\0';
  const char* simple = std::strchr("\"\\ntr", e);
  if (e != '\0' && simple != nullptr) {
    *out += e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e;
    return 2;
  }
  const std::size_t digits = e == 'x' ? 2 : e == 'u' ? 4 : e == 'U' ? 6 : 0;
  char32_t cp = 0;
  std::size_t k = 0;
  for (; digits > 0 && k < digits && backslash + 2 + k < text_.size(); ++k) {
    const int d = hex_digit(text_[backslash + 2 + k]);
    if (d < 0) break;
    cp = cp * 16 + static_cast<char32_t>(d);
  }
  const bool valid = digits > 0 && k == digits && cp > 0 && cp <= 0x10ffff &&
                     !(cp >= 0xd800 && cp <= 0xdfff) && !(e == 'x' && cp > 0x7f);
  if (!valid) {
    *out += '\\';
    return 1;
  }
  append_utf8(cp, out);
  return 2 + digits;
}

void CsgLexer::lex_string(CsgToken* t) {
  const std::size_t b = pos_;
  const std::size_t opened = line_;
  t->kind = CsgToken::Kind::String;
  t->value.clear();
  ++pos_;
  for (;;) {
    if (pos_ >= text_.size()) fail(opened, "a string is never closed (a '\"' is missing)");
    const char c = text_[pos_];
    if (c == '"' && string_ends_at(pos_)) break;
    if (c == '\\') {
      pos_ += decode_escape(pos_, &t->value);
      continue;
    }
    line_ += c == '\n';
    t->value += c;
    ++pos_;
  }
  ++pos_;
  t->text = text_.substr(b, pos_ - b);
}

}  // namespace csgfit::io_detail
