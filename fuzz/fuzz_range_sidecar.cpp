// The JSON sidecar of a 64 x 48 range image: read_range_camera reads it from beside the image
// (the image itself need not exist) and checks the camera it describes.
#include "csgfit/io/range_read.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  csgfit_fuzz::write_scratch("view.json", data, size);
  const std::string image = csgfit_fuzz::scratch_path("view.png");
  return csgfit_fuzz::run([&] { csgfit::read_range_camera(image, 64, 48, {}); });
}
