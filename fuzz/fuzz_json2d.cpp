// A saved 2D result (or a bare tree node, or a 2D morph) as `csgfit export` and `csgfit render`
// read it.
#include "csgfit/io/json.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] {
    csgfit::ModelFrame frame;
    if (csgfit::is_json_morph(text)) {
      std::string source_b;
      csgfit::TurnDirection rotate;
      csgfit::morph_from_json(text, &frame, &source_b, &rotate);
      return;
    }
    csgfit::from_json(text, &frame);
  });
}
