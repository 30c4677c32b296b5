// The outputs every fit to points shares (range images and scans): the tree as .scad and as a
// STEP solid, so that bind_range and bind_points write exactly what the CLI writes.
#pragma once

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "csgfit/model/tree3d.h"

namespace csgfit_python {

/// OpenSCAD 2021.01 source of the tree in model units; `source` goes in the header.
std::string tree_scad(const csgfit::Node3D& tree, const std::string& source, int fn);
/// Writes the tree as a STEP solid (GIL released); InputError when built without OpenCASCADE.
void save_tree_step(const csgfit::Node3D& tree, const std::string& source, const std::string& path);

/// The members every result of a fit to points binds alike: source, sources, diagonal,
/// to_scad(fn) and save_step(path). R holds `sources` and a `fit` with `tree` and `diagonal`.
template <class R>
void def_cloud_outputs(pybind11::class_<R>& c) {
  namespace py = pybind11;
  const auto first = [](const R& r) { return r.sources.empty() ? std::string() : r.sources.front(); };
  c.def_property_readonly("source", first)
      .def_property_readonly("sources", [](const R& r) { return r.sources; })
      .def_property_readonly("diagonal", [](const R& r) { return r.fit.diagonal; },
                             "The diagonal of the points' bounding box.")
      .def(
          "to_scad", [first](const R& r, int fn) { return tree_scad(r.fit.tree, first(r), fn); },
          py::arg("fn") = 96, "OpenSCAD 2021.01 source of the tree (model units).")
      .def(
          "save_step",
          [first](const R& r, const std::string& path) { save_tree_step(r.fit.tree, first(r), path); },
          py::arg("path"), "Writes the tree as a STEP solid (NURBS terminals as B-spline faces).");
}

}  // namespace csgfit_python
