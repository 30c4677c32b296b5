// A saved 3D result as `csgfit export` reads it: is_json3d, then from_json3d.
#include "csgfit/io/json.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] {
    csgfit::is_json3d(text);
    std::string source;
    csgfit::from_json3d(text, &source);
  });
}
