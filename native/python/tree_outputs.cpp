#include "tree_outputs.h"

#include "csgfit/error.h"
#include "progress.h"
#include "scad_writer3d.h"
#ifdef CSGFIT_PY_STEP
#include "step_writer.h"
#endif

namespace csgfit_python {

std::string tree_scad(const csgfit::Node3D& tree, const std::string& source, int fn) {
  if (fn < 3) throw csgfit::InputError("fn must be >= 3");
  csgfit::ScadOptions3D options;
  options.fn = fn;
  options.source = source;
  return csgfit::to_scad(tree, options);
}

void save_tree_step(const csgfit::Node3D& tree, const std::string& source, const std::string& path) {
#ifdef CSGFIT_PY_STEP
  csgfit::StepOptions step;
  step.source = source;
  without_gil([&] { csgfit::write_step(tree, path, step); });
#else
  (void)tree, (void)source;
  throw csgfit::InputError("cannot write '" + path + "': built without OpenCASCADE (no STEP)");
#endif
}

}  // namespace csgfit_python
