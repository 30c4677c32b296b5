// The PLY body, element by element and row by row, ascii or binary: what a row means is the
// caller's (mesh vertices and faces, cloud points).
#pragma once

#include <string>
#include <vector>

#include "io/mesh/ply_header.h"

namespace csgfit::io_detail {

/// What a body reader hands on and what it is asked.
class PlyRowVisitor {
 public:
  virtual ~PlyRowVisitor() = default;
  /// Rows of other elements are skipped (in O(1) when binary with a fixed row size).
  virtual bool wanted(const PlyElement& e) const = 0;
  /// Whether the items of list property `property` of `e` are kept for row(); else skipped.
  virtual bool keeps_list(const PlyElement& e, std::size_t property) const = 0;
  /// One row of a wanted element: a value per property (a list's item count for a list), and
  /// the items of the kept list, if any.
  virtual void row(const PlyElement& e, unsigned long long r, const std::vector<double>& values,
                   const std::vector<double>& list) = 0;
};

/// Reads the body of `d` after header `h`; a body cut short, a bad value or a negative list
/// count is refused with one line naming `path`.
void read_ply_rows(const std::string& path, const std::string& d, const PlyHeader& h,
                   PlyRowVisitor& visitor);

}  // namespace csgfit::io_detail
