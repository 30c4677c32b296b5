// Unorganised points as text ("x y z" or "x y z nx ny nz" per line) in memory.
#include "fuzz_target.h"
#include "io/range/range_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_xyz_points("fuzz.xyz", d, {}); });
}
