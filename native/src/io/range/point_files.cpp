// Point clouds: .xyz text and PLY vertices, with or without normals. A PLY whose header gives
// a width and a height that multiply to its vertex count is an organised scan.

#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_file.h"
#include "io/mesh/ply_body.h"
#include "io/mesh/ply_header.h"
#include "io/range/range_formats.h"
#include "io/text_tokens.h"

namespace csgfit::io_detail {

namespace {

bool finite3(const Vec3& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// Adds a point (and its normal when the file has normals), counting a non-finite one as no
// return. A zero or NaN normal stays for complete_normals to drop as an outlier. Under
// `strict` (a scan file, not a sensor's frame) both are errors naming the point (1-based).
void add_point(RangeScan& scan, const Vec3& p, const Vec3* n, bool strict, unsigned long long index) {
  if (strict && !finite3(p))
    fail(quoted(scan.source) + ": point " + std::to_string(index + 1) + " has a NaN or infinite coordinate");
  if (strict && n && (!finite3(*n) || !((*n)[0] * (*n)[0] + (*n)[1] * (*n)[1] + (*n)[2] * (*n)[2] > 1e-24)))
    fail(quoted(scan.source) + ": the normal of point " + std::to_string(index + 1) +
         " has zero length or is not finite");
  if (!finite3(p)) {
    ++scan.dropped_no_return;
    return;
  }
  scan.points.push_back(p);
  if (n) scan.normals.push_back(*n);
}

[[noreturn]] void too_many_points(const std::string& path, unsigned long long count,
                                  long long limit) {
  fail(quoted(path) + " has " + std::to_string(count) + " points, over the limit of " +
       std::to_string(limit) + " points");
}

// The indices of x y z (and nx ny nz, or normal_x ...) in the vertex element; -1 for none.
struct PlyPointLayout {
  const PlyElement* vertex = nullptr;
  int xyz[3] = {-1, -1, -1};
  int normal[3] = {-1, -1, -1};
  bool has_normals() const { return normal[0] >= 0 && normal[1] >= 0 && normal[2] >= 0; }
};

PlyPointLayout ply_point_layout(const std::string& path, const PlyHeader& h) {
  PlyPointLayout l;
  for (const PlyElement& e : h.elements) {
    if (e.name == "vertex") l.vertex = &e;
  }
  if (!l.vertex) fail(quoted(path) + " has no vertex element (not a point cloud)");
  const char* names[3][3] = {{"x", "nx", "normal_x"}, {"y", "ny", "normal_y"},
                             {"z", "nz", "normal_z"}};
  for (std::size_t i = 0; i < l.vertex->properties.size(); ++i) {
    const PlyProperty& p = l.vertex->properties[i];
    if (p.is_list) continue;
    for (int c = 0; c < 3; ++c) {
      if (p.name == names[c][0]) l.xyz[c] = static_cast<int>(i);
      if (p.name == names[c][1] || p.name == names[c][2]) l.normal[c] = static_cast<int>(i);
    }
  }
  if (l.xyz[0] < 0 || l.xyz[1] < 0 || l.xyz[2] < 0) {
    fail(quoted(path) + ": PLY vertex element has no x, y and z properties");
  }
  return l;
}

// Width and height from "obj_info width 640" / "comment height 480" (or PCL's num_cols and
// num_rows); 0 when the header does not give both or they do not cover the vertices.
void ply_grid_size(const PlyHeader& h, unsigned long long vertices, int* width, int* height) {
  unsigned long long w = 0, ht = 0;
  for (const std::string& comment : h.comments) {
    std::string_view s(comment);
    const std::string_view key = take_token(&s);
    unsigned long long value = 0;
    if (!parse_count(take_token(&s), &value)) continue;
    if (key == "width" || key == "num_cols") w = value;
    if (key == "height" || key == "num_rows") ht = value;
  }
  const bool grid = w > 0 && ht > 0 && w <= vertices && w * ht == vertices;
  *width = grid ? static_cast<int>(w) : 0;
  *height = grid ? static_cast<int>(ht) : 0;
}

class PlyPointRows : public PlyRowVisitor {
 public:
  PlyPointRows(const PlyPointLayout& layout, RangeScan& scan, bool strict)
      : layout_(layout), scan_(scan), strict_(strict) {}
  bool wanted(const PlyElement& e) const override { return &e == layout_.vertex; }
  bool keeps_list(const PlyElement&, std::size_t) const override { return false; }
  void row(const PlyElement&, unsigned long long r, const std::vector<double>& values,
           const std::vector<double>&) override {
    const Vec3 p{values[layout_.xyz[0]], values[layout_.xyz[1]], values[layout_.xyz[2]]};
    const Vec3 n = layout_.has_normals() ? Vec3{values[layout_.normal[0]],
                                                values[layout_.normal[1]],
                                                values[layout_.normal[2]]}
                                         : Vec3{};
    const std::size_t before = scan_.points.size();
    add_point(scan_, p, layout_.has_normals() ? &n : nullptr, strict_, r);
    if (scan_.organised() && scan_.points.size() > before) scan_.pixel.push_back(static_cast<int>(r));
  }

 private:
  const PlyPointLayout& layout_;
  RangeScan& scan_;
  bool strict_;
};

}  // namespace

RangeScan read_xyz_points(const std::string& path, const std::string& d,
                          const RangeReadOptions& options) {
  RangeScan scan;
  scan.source = path;
  Cursor c{d.data(), d.data() + d.size()};
  int columns = -1;  // 3 or 6, fixed by the first point
  unsigned long long count = 0;
  while (!c.at_end()) {
    const long long line = c.line;
    std::string_view rest = take_line(c);
    double v[6];
    int n = 0;
    for (std::string_view t = take_token(&rest); !t.empty() && t[0] != '#';
         t = take_token(&rest)) {
      if (n == 6 || !parse_double(t, &v[n])) {
        fail(quoted(path) + " line " + std::to_string(line) +
             ": expected 'x y z' or 'x y z nx ny nz', found '" + std::string(t.substr(0, 20)) +
             "'");
      }
      ++n;
    }
    if (n == 0) continue;
    if (columns < 0) columns = n;
    if ((n != 3 && n != 6) || n != columns) {
      fail(quoted(path) + " line " + std::to_string(line) + ": " + std::to_string(n) +
           " numbers, where the file's points have " + std::to_string(columns == 6 ? 6 : 3));
    }
    if (++count > static_cast<unsigned long long>(options.max_points)) {
      too_many_points(path, count, options.max_points);
    }
    const Vec3 normal{v[3], v[4], v[5]};
    add_point(scan, {v[0], v[1], v[2]}, n == 6 ? &normal : nullptr, options.strict_points, count - 1);
  }
  check_has_returns(scan);
  return scan;
}

RangeScan read_ply_points(const std::string& path, const std::string& d,
                          const RangeReadOptions& options) {
  const PlyHeader h = read_ply_header(path, d);
  const PlyPointLayout layout = ply_point_layout(path, h);
  const unsigned long long count = layout.vertex->count;
  if (count > static_cast<unsigned long long>(options.max_points)) {
    too_many_points(path, count, options.max_points);
  }
  RangeScan scan;
  scan.source = path;
  ply_grid_size(h, count, &scan.width, &scan.height);
  // Each point takes at least 3 bytes of the body: a hostile count reserves no more than that.
  const std::size_t body = d.size() - std::min(h.body, d.size());
  scan.points.reserve(std::min<std::size_t>(count, body / 3));
  PlyPointRows rows(layout, scan, options.strict_points && !scan.organised());
  read_ply_rows(path, d, h, rows);
  check_has_returns(scan);
  return scan;
}

}  // namespace csgfit::io_detail
