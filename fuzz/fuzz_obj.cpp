// Wavefront OBJ in memory: io_detail::read_obj, what read_mesh calls for a .obj file.
#include "fuzz_target.h"
#include "io/mesh/formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string d = csgfit_fuzz::as_text(data, size);
  csgfit::MeshReadInfo info;
  return csgfit_fuzz::run([&] { csgfit::io_detail::read_obj("fuzz.obj", d, {}, &info); });
}
