// CancelToken, FitProgress and the bridge from the solver's progress reports to Python.
#include "progress.h"

#include <string>

#include "bindings.h"

namespace csgfit_python {

bool ProgressBridge::operator()(const csgfit::FitProgress& progress) {
  if (stop_.load() || (cancel_ && cancel_->load())) return false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(50) && progress.fraction < 1.0) return true;
    last_ = now;
  }
  py::gil_scoped_acquire gil;
  try {
    // Lets Ctrl-C stop a fit run from the main thread (a no-op on other threads).
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!callback_.is_none()) {
      py::object answer = callback_(progress);
      if (answer.ptr() == Py_False) stop_.store(true);
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
    stop_.store(true);
  }
  return !stop_.load();
}

void check_progress(const py::object& progress) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw csgfit::InputError("progress must be callable or None");
}

void bind_progress(py::module_& m) {
  py::class_<CancelToken>(m, "CancelToken",
                          "A flag to stop a running fit from another thread.\n\n"
                          "Pass it as fit_image(..., cancel=token) and call token.cancel() from "
                          "any thread: the fit returns promptly with the best tree found so "
                          "far and stats.stop_reason == 'cancelled'.")
      .def(py::init<>())
      .def("cancel", &CancelToken::cancel, "Ask the fit to stop (thread-safe).")
      .def("reset", &CancelToken::reset, "Clear the flag so the token can be reused.")
      .def_property_readonly("cancelled", &CancelToken::cancelled,
                             "Whether cancel() was called (and not reset since).");

  py::class_<csgfit::FitProgress>(m, "FitProgress",
                                  "A progress report passed to the progress callback.")
      .def_readonly("fraction", &csgfit::FitProgress::fraction,
                    "0..1 of the time budget or of convergence, whichever is ahead.")
      .def_readonly("best_score", &csgfit::FitProgress::best_score,
                    "Score of the best tree so far (lower is better).")
      .def_readonly("best_primitives", &csgfit::FitProgress::best_primitives,
                    "Primitives in the best tree so far.")
      .def_readonly("evaluations", &csgfit::FitProgress::evaluations, "Tree evaluations so far.")
      .def_readonly("seconds", &csgfit::FitProgress::seconds, "Wall time so far.")
      .def("__repr__", [](const csgfit::FitProgress& p) {
        return "FitProgress(fraction=" + std::to_string(p.fraction) +
               ", best_score=" + std::to_string(p.best_score) +
               ", best_primitives=" + std::to_string(p.best_primitives) + ")";
      });
}

}  // namespace csgfit_python
