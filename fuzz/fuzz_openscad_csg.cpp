// An OpenSCAD CSG program as `csgfit optimize` reads a .csg: parse_openscad_csg, then
// program_from_csg (matrices, primitives, extrusions of 2D trees, opaque leaves).
#include "csgfit/io/openscad_program.h"
#include "fuzz_target.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = csgfit_fuzz::as_text(data, size);
  return csgfit_fuzz::run([&] {
    const auto calls = csgfit::parse_openscad_csg(text, "fuzz.csg");
    csgfit::program_from_csg(calls, text, "fuzz.csg");
  });
}
