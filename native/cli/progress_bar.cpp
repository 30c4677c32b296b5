#include "progress_bar.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace csgfit::cli {

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled && isatty(STDERR_FILENO)) {}

bool ProgressBar::update(const FitProgress& p) {
  if (!enabled_) return true;
  const int width = 30;
  const int filled = static_cast<int>(std::lround(p.fraction * width));
  std::fprintf(stderr, "\r[%s%s] %3d%%  score %.0f  %zu primitives  %zu evaluations  %.1f s ",
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), '.').c_str(),
               static_cast<int>(std::lround(p.fraction * 100)), p.best_score, p.best_primitives,
               p.evaluations, p.seconds);
  std::fflush(stderr);
  drawn_ = true;
  return true;
}

void ProgressBar::finish() {
  if (drawn_) std::fprintf(stderr, "\r%*s\r", 110, "");
}

}  // namespace csgfit::cli
