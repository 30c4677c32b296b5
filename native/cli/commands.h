// The subcommands of csgfit. Each registers itself and its options on the application and
// hands back what runs it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

namespace csgfit::cli {

/// A registered subcommand: parsing fills its options, `run` does its work and throws
/// InputError (or std::invalid_argument) for bad input.
struct Command {
  CLI::App* app;
  std::function<void()> run;
};

/// Registers subcommand `name`: `add_options` binds its options to an Args that the command
/// owns, and `run` runs on them once they are parsed.
template <class Args>
Command make_command(CLI::App& app, const char* name, const char* description,
                     void (*add_options)(CLI::App&, Args&), void (*run)(const Args&)) {
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand(name, description);
  add_options(*command, *args);
  return {command, [args, run] { run(*args); }};
}

/// csgfit image: a bitmap to a 2D CSG tree.
Command add_image_command(CLI::App& app);
/// csgfit export: a saved .json result (2D or 3D) to another format.
Command add_export_command(CLI::App& app);
/// csgfit render: the solver's raster of a saved 2D result, as PNG.
Command add_render_command(CLI::App& app);
/// csgfit mesh: a triangle mesh or voxel grid to a 3D CSG tree.
Command add_mesh_command(CLI::App& app);

/// csgfit range: range images or point clouds to a 3D CSG tree (seed 002).
Command add_range_command(CLI::App& app);
/// csgfit points (cmd_points.cpp): point clouds to CSG with NURBS terminals (seed 004).
Command add_points_command(CLI::App& app);

/// csgfit optimize: a CSG tree to a smaller one of the same solid (seed 001).
Command add_optimize_command(CLI::App& app);
/// csgfit inflate: seed 001's redundancy generator.
Command add_inflate_command(CLI::App& app);
/// csgfit morph: two shapes to two trees of one structure (seed 000's morphing).
Command add_morph_command(CLI::App& app);

}  // namespace csgfit::cli
