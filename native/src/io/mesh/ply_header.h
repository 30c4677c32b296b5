// The PLY header: format, elements and their properties, read before the body.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace csgfit::io_detail {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

/// Bytes a value of type t takes in a binary body.
std::size_t ply_size(PlyType t);

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
  PlyType type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kLittle, kBig };

/// What the header declares; refused with one line naming the file and line when malformed.
struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body = 0;  // offset of the data after the end_header line
  /// The text after each "comment" and "obj_info" keyword (where an organised cloud keeps
  /// its width and height), in order.
  std::vector<std::string> comments;
};

/// Checks the "ply" signature and reads the header up to end_header.
PlyHeader read_ply_header(const std::string& path, const std::string& d);

}  // namespace csgfit::io_detail
