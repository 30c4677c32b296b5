// Netpbm (P1..P6) in memory: the header, then, within read_image's default pixel limit (which
// read_image checks before it decodes), the raster.
#include <vector>

#include "csgfit/io/image.h"
#include "fuzz_target.h"
#include "io/image/netpbm.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace csgfit::image_detail;
  static const bool verbose = std::getenv("CSGFIT_FUZZ_VERBOSE") != nullptr;
  std::string reason = "not a Netpbm signature";
  NetpbmHeader header;
  std::vector<std::uint8_t> pixels;
  if (looks_like_netpbm(data, size) && parse_netpbm_header(data, size, &header, &reason)) {
    if (header.width <= 0 || header.height <= 0 ||
        header.width > csgfit::ImageReadOptions{}.max_pixels / header.height) {
      reason = "over the pixel limit";
    } else if (decode_netpbm(data, size, header, &pixels, &reason)) {
      reason = "read";
    }
  }
  if (verbose) std::fprintf(stderr, "%s\n", reason.c_str());
  return 0;
}
