// The `csgfit` command line: parses, runs the one subcommand given, and is the one place that
// turns errors into messages and exit status (2 for bad input or usage, 1 for the rest).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "output.h"

using namespace csgfit;

namespace {

// Scripts (the STEP tests among them) read what this build can write from here.
std::string version_line() {
  std::string line = std::string("csgfit ") + CSGFIT_VERSION;
  if (!cli::has_step_support()) line += " (without STEP: CSGFIT_BUILD_OCCT=OFF)";
  return line;
}

// -1 when the command line parsed and a command is to run, else the exit status.
int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --help-all, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    std::cerr << "csgfit: " << printable_message(msg) << " (see csgfit --help)\n";
    return 2;
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"csgfit: turn bitmaps into compact, editable CSG trees (OpenSCAD, JSON, FreeCAD)"};
  app.set_version_flag("--version", version_line());
  app.require_subcommand(1);
  const std::vector<cli::Command> commands = {
      cli::add_image_command(app), cli::add_export_command(app), cli::add_render_command(app),
      cli::add_mesh_command(app), cli::add_range_command(app), cli::add_points_command(app),
      cli::add_optimize_command(app), cli::add_inflate_command(app), cli::add_morph_command(app)};
  if (const int status = parse(app, argc, argv); status >= 0) return status;

  try {
    // Every output of the command lands at the end, together, or none does.
    OutputBatch outputs;
    for (const cli::Command& command : commands)
      if (*command.app) command.run();
    outputs.commit();
    return 0;
  } catch (const InputError& e) {
    std::cerr << "csgfit: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "csgfit: " << printable_message(e.what()) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // The memory budget refuses known large allocations up front; this is the rest.
    std::cerr << "csgfit: out of memory (try a smaller input, --resolution or --max-memory)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "csgfit: internal error: " << printable_message(e.what()) << "\n";
    return 1;
  }
}
