// What a fitting command shows on stderr while it runs.
#pragma once

#include "csgfit/search/stats.h"

namespace csgfit::cli {

/// A one-line bar redrawn in place; only when stderr is a terminal, so that logs and pipes get
/// no carriage returns.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  /// Redraws the bar; always true (the command never cancels its fit).
  bool update(const FitProgress& p);
  /// Clears the bar so that what follows starts on a clean line.
  void finish();
  /// The callback to hand to a fit.
  ProgressCallback callback() {
    return [this](const FitProgress& p) { return update(p); };
  }

 private:
  bool enabled_;
  bool drawn_ = false;
};

}  // namespace csgfit::cli
