// BMP through read_image, the path every image command takes (header, limits, decode, grey).
// Images over 2^18 pixels are refused (as over max_pixels) before they are decoded: the header
// and limit paths are the same, and a run is not spent decoding legitimately large pictures.
#include "csgfit/io/image.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = csgfit_fuzz::write_scratch("input.bmp", data, size);
  csgfit::ImageReadOptions options;
  options.max_pixels = 1 << 18;
  return csgfit_fuzz::run([&] { csgfit::read_image(path, options); });
}
