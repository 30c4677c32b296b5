// JPEG through read_image, the path every image command takes (header, limits, decode, grey).
#include "csgfit/io/image.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = csgfit_fuzz::write_scratch("input.jpg", data, size);
  return csgfit_fuzz::run([&] { csgfit::read_image(path); });
}
