// read_range: the format by extension, the file read whole under a size limit, then normals.

#include <algorithm>
#include <climits>
#include <optional>
#include <string>
#include <vector>

#include "csgfit/features/point_normals.h"
#include "csgfit/io/range_read.h"
#include "io/input_file.h"
#include "io/range/range_formats.h"

namespace csgfit {

namespace {

// The largest file worth reading for a limit of `items` values of `bytes_each` bytes (text
// may spend 40 bytes on a number), and never past what stb and the parsers index with int.
long long file_limit(long long items, long long bytes_each) {
  const long long cap = INT_MAX;
  if (items <= 0) return 1 << 16;
  return items > cap / bytes_each ? cap : std::max<long long>(items * bytes_each, 1 << 16);
}

}  // namespace

RangeScan read_range(const std::string& path, const RangeReadOptions& options) {
  namespace d = io_detail;
  const std::string ext = d::lower_extension(path);
  const bool image = ext == "png" || ext == "npy";
  if (!image && ext != "ply" && ext != "xyz") {
    d::fail(d::quoted(path) +
            ": unknown range format (use .png or .npy with a sidecar, .ply or .xyz)");
  }
  // PNG compresses: its limit is checked on the header's size, not on the file's.
  const long long max_bytes = image ? file_limit(options.max_pixels, 24)
                                    : file_limit(options.max_points, ext == "xyz" ? 240 : 64);
  const std::string data =
      d::read_whole_file(path, max_bytes, "over the range reader's limit",
                         ext == "xyz" ? d::FileContent::Text : d::FileContent::Binary);
  PointNormalOptions normals;
  RangeScan scan;
  if (ext == "png") {
    scan = d::read_depth_png(path, data, options);
  } else if (ext == "npy") {
    scan = d::read_npy_range(path, data, options, &normals.view_direction);
  } else if (ext == "ply") {
    scan = d::read_ply_points(path, data, options);
  } else {
    scan = d::read_xyz_points(path, data, options);
  }
  complete_normals(scan, normals);
  if (scan.points.empty()) {
    d::fail(d::quoted(path) + " has no usable points: all " +
            d::count_text(scan.dropped_outliers, "point") + " are outliers or have no normal");
  }
  return scan;
}

std::vector<RangeScan> read_ranges(const std::vector<std::string>& paths,
                                   const RangeReadOptions& options) {
  if (paths.empty()) io_detail::fail("no range image or point cloud given");
  std::vector<RangeScan> scans;
  scans.reserve(paths.size());
  for (const std::string& p : paths) scans.push_back(read_range(p, options));
  return scans;
}

}  // namespace csgfit
