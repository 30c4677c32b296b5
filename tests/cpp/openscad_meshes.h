// Meshes made the way users make them: an OpenSCAD program rendered to STL by OpenSCAD itself,
// so that tests see real tessellations ($fn polygons, revolved profiles, CGAL's triangulation).
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "csgfit/io/mesh_read.h"
#include "csgfit/model/mesh.h"

namespace csgfit::testing {

inline bool have_openscad() { return std::system("command -v openscad >/dev/null 2>&1") == 0; }

/// The mesh OpenSCAD renders from `program` (an empty mesh and a test failure when it cannot).
inline TriangleMesh openscad_mesh(const std::string& program) {
  std::string dir = (std::filesystem::temp_directory_path() / "csgfit_scad_mesh_XXXXXX").string();
  if (!::mkdtemp(dir.data())) return {};
  const std::string scad = dir + "/part.scad", stl = dir + "/part.stl";
  std::ofstream(scad) << program;
  const std::string cmd = "openscad -q -o '" + stl + "' '" + scad + "' >/dev/null 2>&1";
  TriangleMesh mesh;
  if (std::system(cmd.c_str()) == 0) {
    mesh = read_mesh(stl);
  } else {
    ADD_FAILURE() << "openscad could not render:\n" << program;
  }
  std::filesystem::remove_all(dir);
  return mesh;
}

}  // namespace csgfit::testing
