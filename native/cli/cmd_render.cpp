#include "commands.h"
#include "csgfit/io/image.h"
#include "csgfit/io/json.h"
#include "option_checks.h"
#include "output.h"

namespace csgfit::cli {

namespace {

struct RenderArgs {
  std::string input, output;
};

void add_render_options(CLI::App& renderer, RenderArgs& a) {
  renderer.add_option("input", a.input, "csgfit .json result")->required();
  renderer.add_option("-o,--output", a.output, "PNG")->required();
  add_memory_option(renderer);
}

void run_render(const RenderArgs& a) {
  check_png_output(a.output, "render -o");
  const FitResult result = from_json(read_json_file(a.input));
  write_bitmap_png(a.output, render(result.tree, result.width, result.height));
}

}  // namespace

Command add_render_command(CLI::App& app) {
  return make_command(app, "render", "draw a csgfit .json result as the solver rasterises it",
                      add_render_options, run_render);
}

}  // namespace csgfit::cli
