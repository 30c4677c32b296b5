// A 16-bit depth PNG in memory (io_detail::read_depth_png), with an orthographic camera given
// as intrinsics so that no sidecar is needed.
#include "fuzz_target.h"
#include "io/range/range_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  csgfit::RangeReadOptions options;
  options.intrinsics.pixel_size = 1.0;
  const std::string path = csgfit_fuzz::scratch_path("depth.png");  // no sidecar beside it
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_depth_png(path, d, options); });
}
