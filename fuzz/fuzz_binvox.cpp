// A binvox voxel grid in memory: io_detail::read_binvox, what read_voxels calls for .binvox.
#include "fuzz_target.h"
#include "io/voxels/formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_binvox("fuzz.binvox", d, {}); });
}
