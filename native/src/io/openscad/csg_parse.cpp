// The .csg grammar: statements `name(args);`, `name(args) { statements }` and
// `name(args) statement`. Calls and vectors are parsed with explicit stacks, not recursion, so
// that nesting is limited by max_depth with a message rather than by the thread's stack.

#include <utility>
#include <vector>

#include "csgfit/io/openscad_csg.h"
#include "io/openscad/csg_lexer.h"

namespace csgfit {

const ScadValue* ScadCall::argument(std::string_view wanted) const {
  for (const auto& argument : arguments) {
    if (argument.first == wanted) return &argument.second;
  }
  return nullptr;
}

namespace {

using io_detail::CsgToken;

class CsgParser {
 public:
  CsgParser(std::string_view text, std::string_view file, std::size_t max_depth)
      : lex_(text, file), max_depth_(max_depth) {
    advance();
  }

  std::vector<ScadCall> parse();

 private:
  // A call whose children are being read; `braced` is false for `name(args) child;`.
  struct OpenCall {
    ScadCall call;
    bool braced;
  };

  void advance() { lex_.next(&tok_); }
  [[noreturn]] void fail(const std::string& what) const { lex_.fail(tok_.line, what); }
  [[noreturn]] void unexpected(const char* expected) const;
  void expect(char c, const char* expected);
  void statement();
  void close_brace();
  void refuse_modifier() const;
  void call_head(ScadCall* call);
  void argument(ScadCall* call);
  ScadValue value();
  ScadValue scalar();
  void check_depth(std::size_t depth, const char* what) const;
  void finish(ScadCall call);
  [[noreturn]] void fail_truncated() const;

  io_detail::CsgLexer lex_;
  std::size_t max_depth_;
  CsgToken tok_;
  std::vector<OpenCall> open_;
  std::vector<ScadCall> top_;
  const ScadCall* heading_ = nullptr;  // the call whose arguments are being read
};

std::string describe(const CsgToken& t) {
  switch (t.kind) {
    case CsgToken::Kind::End: return "the end of the file";
    case CsgToken::Kind::String: return "a string";
    default: return "'" + std::string(t.text.substr(0, 40)) + "'";
  }
}

void CsgParser::unexpected(const char* expected) const {
  if (tok_.kind == CsgToken::Kind::End) fail_truncated();
  fail("expected " + std::string(expected) + ", found " + describe(tok_));
}

void CsgParser::expect(char c, const char* expected) {
  if (!tok_.is(c)) unexpected(expected);
  advance();
}

void CsgParser::fail_truncated() const {
  if (heading_ != nullptr) {
    lex_.fail(tok_.line, "the file ends inside the arguments of " + heading_->name +
                             "() from line " + std::to_string(heading_->line) + " (it is truncated)");
  }
  if (open_.empty()) lex_.fail(tok_.line, "the file ends inside a call (it is truncated)");
  const ScadCall& c = open_.back().call;
  lex_.fail(tok_.line, "the file ends inside " + c.name + "() from line " +
                           std::to_string(c.line) + " (it is truncated, or a '}' is missing)");
}

void CsgParser::check_depth(std::size_t depth, const char* what) const {
  if (depth > max_depth_) {
    fail(std::string(what) + " nested deeper than " + std::to_string(max_depth_) +
         " levels (the reader's max_depth)");
  }
}

void CsgParser::refuse_modifier() const {
  const char m = tok_.text[0];
  const char* kind = m == '!' ? "root" : m == '#' ? "debug" : m == '%' ? "background" : "disable";
  fail("the " + std::string(kind) + " modifier '" + std::string(1, m) +
       "' is not supported: remove it from the model (OpenSCAD keeps it in the .csg)");
}

std::vector<ScadCall> CsgParser::parse() {
  while (tok_.kind != CsgToken::Kind::End) statement();
  if (!open_.empty()) fail_truncated();
  return std::move(top_);
}

void CsgParser::statement() {
  if (tok_.is(';')) {
    if (!open_.empty() && !open_.back().braced) unexpected("a child statement");
    advance();
    return;
  }
  if (tok_.is('}')) return close_brace();
  if (tok_.is('!') || tok_.is('#') || tok_.is('%') || tok_.is('*')) refuse_modifier();
  if (tok_.kind != CsgToken::Kind::Name) unexpected("a module call");
  check_depth(open_.size() + 1, "calls");
  ScadCall call;
  call_head(&call);
  if (tok_.is(';')) {
    call.source_end = tok_.offset + 1;
    advance();
    return finish(std::move(call));
  }
  const bool braced = tok_.is('{');
  if (braced) advance();
  open_.push_back({std::move(call), braced});
}

void CsgParser::close_brace() {
  if (open_.empty()) fail("a '}' without an open '{'");
  if (!open_.back().braced) unexpected("a child statement");
  ScadCall call = std::move(open_.back().call);
  open_.pop_back();
  call.source_end = tok_.offset + 1;
  advance();
  finish(std::move(call));
}

// Hands a complete call to its parent; a parent without braces is complete with it.
void CsgParser::finish(ScadCall call) {
  while (!open_.empty()) {
    OpenCall& parent = open_.back();
    parent.call.children.push_back(std::move(call));
    if (parent.braced) return;
    call = std::move(parent.call);
    call.source_end = call.children.back().source_end;
    open_.pop_back();
  }
  top_.push_back(std::move(call));
}

void CsgParser::call_head(ScadCall* call) {
  call->name = std::string(tok_.text);
  call->line = tok_.line;
  call->source_begin = tok_.offset;
  heading_ = call;
  advance();
  expect('(', "'(' after a module name");
  while (!tok_.is(')')) {
    argument(call);
    if (tok_.is(',')) {
      advance();
    } else if (!tok_.is(')')) {
      unexpected("',' or ')' in the arguments");
    }
  }
  heading_ = nullptr;
  advance();
}

void CsgParser::argument(ScadCall* call) {
  std::string name;
  if (tok_.kind == CsgToken::Kind::Name && tok_.text != "true" && tok_.text != "false" &&
      tok_.text != "undef") {
    name = std::string(tok_.text);
    advance();
    expect('=', "'=' after an argument name");
  }
  call->arguments.emplace_back(std::move(name), value());
}

ScadValue CsgParser::scalar() {
  ScadValue v;
  if (tok_.kind == CsgToken::Kind::Number) {
    v.type = ScadValue::Type::Number;
    v.number = tok_.number;
  } else if (tok_.kind == CsgToken::Kind::String) {
    v.type = ScadValue::Type::String;
    v.text = std::move(tok_.value);
  } else if (tok_.text == "true" || tok_.text == "false") {
    v.type = ScadValue::Type::Bool;
    v.boolean = tok_.text == "true";
  } else if (tok_.text != "undef" || tok_.kind != CsgToken::Kind::Name) {
    unexpected("a value (a number, true, false, undef, a string or a vector)");
  }
  advance();
  return v;
}

// A value; vectors are kept on a stack of those still open, each closed by its ']'.
ScadValue CsgParser::value() {
  std::vector<ScadValue> open;
  for (;;) {
    ScadValue v;
    if (tok_.is('[')) {
      check_depth(open.size() + 1, "vectors");
      open.emplace_back().type = ScadValue::Type::Vector;
      advance();
      if (!tok_.is(']')) continue;
      v = std::move(open.back());
      open.pop_back();
      advance();
    } else {
      v = scalar();
    }
    for (;;) {
      if (open.empty()) return v;
      open.back().items.push_back(std::move(v));
      if (tok_.is(',')) {
        advance();
        if (!tok_.is(']')) break;
      } else if (!tok_.is(']')) {
        unexpected("',' or ']' in a vector");
      }
      v = std::move(open.back());
      open.pop_back();
      advance();
    }
  }
}

}  // namespace

std::vector<ScadCall> parse_openscad_csg(std::string_view text, std::string_view file_name,
                                         std::size_t max_depth) {
  return CsgParser(text, file_name, max_depth).parse();
}

}  // namespace csgfit
