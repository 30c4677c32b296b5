// The native half of the `csgfit` Python package. The binding stays thin on purpose: it turns
// numpy arrays and files into the solver's types, runs the pipeline entries with the GIL
// released, and hands results back in the solver's own units; the Python package
// (csgfit/*.py) turns them into model-unit objects, so the user-facing API can evolve without
// recompiling.
#include "bindings.h"

PYBIND11_MODULE(_csgfit, m) {
  m.doc() =
      "Native core of the csgfit package: bitmap, mesh, voxel and range to CSG tree "
      "fitting. Use the `csgfit` package (csgfit.fit_image, csgfit.fit_mesh, csgfit.fit_voxels, "
      "csgfit.fit_range, csgfit.fit_points) rather than this module directly.";
  csgfit_python::bind_errors(m);
  csgfit_python::bind_progress(m);
  csgfit_python::bind_io(m);
  csgfit_python::bind_optimize(m);
  csgfit_python::bind_morph(m);
  csgfit_python::bind_2d(m);
  csgfit_python::bind_3d(m);
  csgfit_python::bind_range(m);
  csgfit_python::bind_points(m);
}
