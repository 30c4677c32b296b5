// The tokens of OpenSCAD's .csg text, for csg_parse.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace csgfit::io_detail {

struct CsgToken {
  enum class Kind { Name, Number, String, Punct, End };
  Kind kind = Kind::End;
  std::string_view text;  // the token as written
  std::string value;      // a string's decoded content
  double number = 0;
  std::size_t offset = 0;  // of the token's first byte
  std::size_t line = 1;

  bool is(char c) const { return kind == Kind::Punct && text.size() == 1 && text[0] == c; }
};

/// Splits .csg text into names ($fn, true and inf included), numbers, strings and the
/// punctuation ( ) { } [ ] , ; = ! # % *. Comments are skipped. Refuses (InputError
/// "FILE:LINE: ...") what no .csg holds: other characters, bad or non-finite numbers,
/// unterminated strings and comments.
class CsgLexer {
 public:
  CsgLexer(std::string_view text, std::string_view file) : text_(text), file_(file) {}

  /// The next token; Kind::End (repeatedly) at the end of the text.
  void next(CsgToken* token);

  /// Throws InputError("FILE:LINE: what").
  [[noreturn]] void fail(std::size_t line, const std::string& what) const;

 private:
  void skip_space_and_comments();
  void lex_number(CsgToken* token);
  void lex_string(CsgToken* token);
  bool string_ends_at(std::size_t quote) const;
  std::size_t decode_escape(std::size_t backslash, std::string* out) const;
  char peek(std::size_t ahead = 0) const {
    return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0';
  }

  std::string_view text_;
  std::string_view file_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

}  // namespace csgfit::io_detail
