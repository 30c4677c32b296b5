// A .npy range input in memory (io_detail::read_npy_range): an H x W float depth map (with an
// orthographic camera given as intrinsics) or an H x W x 3 organised cloud.
#include "fuzz_target.h"
#include "io/range/range_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  csgfit::RangeReadOptions options;
  options.intrinsics.pixel_size = 1.0;
  const std::string path = csgfit_fuzz::scratch_path("range.npy");  // no sidecar beside it
  std::optional<csgfit::Vec3> view;
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_npy_range(path, d, options, &view); });
}
