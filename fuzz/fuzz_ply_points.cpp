// PLY points in memory (io_detail::read_ply_points): organised when the header's width and
// height multiply to the vertex count, with or without normals.
#include "fuzz_target.h"
#include "io/range/range_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_ply_points("fuzz.ply", d, {}); });
}
