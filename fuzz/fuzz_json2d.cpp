// A saved 2D result (or a bare tree node) as `csgfit export` and `csgfit render` read it.
#include "csgfit/io/json.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] {
    csgfit::ModelFrame frame;
    csgfit::from_json(text, &frame);
  });
}
