// Progress, cancelling and the GIL around a fit: what every fit entry of the module shares.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "csgfit/error.h"
#include "csgfit/search/stats.h"

namespace csgfit_python {

namespace py = pybind11;

/// A flag another Python thread sets to stop a running fit. Shared ownership so that the
/// solver's view of it outlives any Python-side juggling of the token object.
class CancelToken {
 public:
  void cancel() { flag_->store(true); }
  void reset() { flag_->store(false); }
  bool cancelled() const { return flag_->load(); }
  const std::atomic<bool>* flag() const { return flag_.get(); }

 private:
  std::shared_ptr<std::atomic<bool>> flag_ = std::make_shared<std::atomic<bool>>(false);
};

/// Bridges the solver's progress reports to a Python callable. The solver may call from any
/// of its threads; the GIL is taken only for the Python call, and calls are throttled so that
/// a fast search is not slowed down by the interpreter.
class ProgressBridge {
 public:
  ProgressBridge(py::object callback, const std::atomic<bool>* cancel)
      : callback_(std::move(callback)), cancel_(cancel) {}

  bool operator()(const csgfit::FitProgress& progress);
  /// Re-raises an exception the callback raised (call with the GIL held).
  void rethrow_if_failed() {
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  py::object callback_;
  const std::atomic<bool>* cancel_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
  std::exception_ptr error_;
};

/// Throws InputError unless `progress` is None or callable.
void check_progress(const py::object& progress);

/// Runs `work()` with the GIL released: long reads, voxelising and rendering, so that other
/// Python threads (a GUI) keep running meanwhile.
template <class Work>
auto without_gil(Work&& work) {
  py::gil_scoped_release release;
  return work();
}

/// Runs `fit(progress callback, cancel flag)` with the GIL released and the Python callback
/// bridged. The solver refuses bad options with std::invalid_argument; Python users get them as
/// csgfit.InputError with the same one-line message. An exception the callback raised is
/// re-raised here, after the solver has stopped.
template <class Fit>
auto run_fit_released(const py::object& progress, const CancelToken* cancel, Fit&& fit) {
  check_progress(progress);
  // The token's own flag is what the solver polls; a False from the callback stops the search
  // through the callback's return value.
  const std::atomic<bool>* flag = cancel ? cancel->flag() : nullptr;
  ProgressBridge bridge(progress, flag);
  const csgfit::ProgressCallback callback = [&bridge](const csgfit::FitProgress& p) {
    return bridge(p);
  };
  auto result = without_gil([&] {
    try {
      return fit(callback, flag);
    } catch (const std::invalid_argument& e) {
      throw csgfit::InputError(e.what());
    }
  });
  bridge.rethrow_if_failed();
  return result;
}

}  // namespace csgfit_python
