#include "io/mesh/ply_header.h"

#include <cstring>
#include <string_view>
#include <utility>

#include "io/input_file.h"
#include "io/sniff.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

bool ply_type(std::string_view name, PlyType* t) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [n, type] : kTypes) {
    if (name == n) {
      *t = type;
      return true;
    }
  }
  return false;
}

[[noreturn]] void bad_header(const std::string& path, const Cursor& c, const std::string& what) {
  fail(quoted(path) + " line " + std::to_string(c.line) + ": bad PLY header (" + what + ")");
}

// "property [list COUNT_TYPE] TYPE NAME", after the keyword; `c` is just past the line.
PlyProperty parse_property(const std::string& path, const Cursor& c, std::string_view line) {
  PlyProperty p;
  std::string_view t = take_token(&line);
  if (t == "list") {
    p.is_list = true;
    if (!ply_type(take_token(&line), &p.count_type)) {
      bad_header(path, c, "unknown list count type");
    }
    if (p.count_type == PlyType::kFloat32 || p.count_type == PlyType::kFloat64) {
      bad_header(path, c, "a list count must be an integer type");
    }
    t = take_token(&line);
  }
  if (!ply_type(t, &p.type)) bad_header(path, c, "unknown property type '" + std::string(t) + "'");
  p.name = std::string(take_token(&line));
  if (p.name.empty()) bad_header(path, c, "property without a name");
  return p;
}

}  // namespace

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 1;
}

PlyHeader read_ply_header(const std::string& path, const std::string& d) {
  if (!(starts_with(d, "ply\n") || starts_with(d, "ply\r"))) {
    const std::string what = sniff(d);
    if (!what.empty()) fail_mislabelled(path, what, "a PLY mesh");
    fail(quoted(path) + " is not a PLY mesh (it does not start with 'ply')");
  }
  const std::size_t header_end = d.find("end_header");
  if (header_end == std::string::npos) fail(quoted(path) + " is truncated (no 'end_header' line)");
  Cursor c{d.data(), d.data() + header_end};
  skip_line(c);  // "ply"
  PlyHeader h;
  bool have_format = false;
  while (!c.at_end()) {
    std::string_view line = take_line(c);
    const std::string_view key = take_token(&line);
    if (key.empty()) continue;
    if (key == "comment" || key == "obj_info") {
      h.comments.emplace_back(line);
      continue;
    }
    if (key == "format") {
      const std::string_view f = take_token(&line);
      if (f == "ascii") {
        h.format = PlyFormat::kAscii;
      } else if (f == "binary_little_endian") {
        h.format = PlyFormat::kLittle;
      } else if (f == "binary_big_endian") {
        h.format = PlyFormat::kBig;
      } else {
        bad_header(path, c, "unknown format '" + std::string(f) + "'");
      }
      have_format = true;
    } else if (key == "element") {
      PlyElement e;
      e.name = std::string(take_token(&line));
      if (e.name.empty() || !parse_count(take_token(&line), &e.count)) {
        bad_header(path, c, "element needs a name and a count");
      }
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) bad_header(path, c, "property before any element");
      h.elements.back().properties.push_back(parse_property(path, c, line));
    } else {
      bad_header(path, c, "unknown keyword '" + std::string(key) + "'");
    }
  }
  if (!have_format) bad_header(path, c, "no format line");
  h.body = header_end + std::strlen("end_header");
  while (h.body < d.size() && (d[h.body] == ' ' || d[h.body] == '\r')) ++h.body;
  if (h.body < d.size() && d[h.body] == '\n') ++h.body;
  return h;
}

}  // namespace csgfit::io_detail
