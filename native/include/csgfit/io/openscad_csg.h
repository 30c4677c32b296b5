// Reading OpenSCAD's flattened CSG format (.csg), the input of `csgfit optimize`.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace csgfit {

/// One argument value as OpenSCAD writes it in a .csg: a number, a boolean, a string, undef,
/// or a vector of values (nested vectors for multmatrix and polygon points).
struct ScadValue {
  enum class Type { Undef, Number, Bool, String, Vector };
  Type type = Type::Undef;
  double number = 0;
  bool boolean = false;
  std::string text;
  std::vector<ScadValue> items;

  bool is_undef() const { return type == Type::Undef; }
  bool is_number() const { return type == Type::Number; }
  bool is_bool() const { return type == Type::Bool; }
  bool is_string() const { return type == Type::String; }
  bool is_vector() const { return type == Type::Vector; }
};

/// One module call of a .csg: name, arguments in order (positional ones have an empty name),
/// children, and where its text is (byte offsets into the parsed text, children included,
/// for keeping unknown calls like hull() verbatim).
struct ScadCall {
  std::string name;
  std::vector<std::pair<std::string, ScadValue>> arguments;
  std::vector<ScadCall> children;
  std::size_t line = 0;                          // 1-based
  std::size_t source_begin = 0, source_end = 0;  // [begin, end) of the call's text, incl. the ';' or '}'

  /// The first argument called `name`; nullptr when absent.
  const ScadValue* argument(std::string_view name) const;
};

/// Parses OpenSCAD's CSG text (what `openscad -o x.csg` writes, also FreeCAD's OpenSCAD
/// workbench's format) into its top-level calls. Throws InputError ("FILE:LINE: what is wrong")
/// on a syntax error, a truncated file, NaN/inf numbers, a modifier (! # % *), or nesting
/// (of calls or of vectors) deeper than max_depth.
std::vector<ScadCall> parse_openscad_csg(std::string_view text, std::string_view file_name,
                                         std::size_t max_depth = 4096);

/// Runs OpenSCAD on a .scad (`openscad -o TMP.csg IN.scad`, TMP in a fresh temp directory that
/// is removed afterwards) and returns the flattened .csg text. InputError when `openscad` is not
/// on PATH, or with OpenSCAD's own first ERROR/WARNING-about-parse line when it fails.
std::string flatten_scad_with_openscad(const std::string& scad_path);

}  // namespace csgfit
