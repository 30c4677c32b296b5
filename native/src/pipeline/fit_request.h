// Internal to pipeline/: what every fit shares before and while it runs: the checks of what it
// is asked, and the points of its time budget.
#pragma once

#include <chrono>
#include <stdexcept>

namespace csgfit {

/// Throws std::invalid_argument, naming the problem, for an empty target, no primitive kind or a
/// budget that is not positive (NaN included).
template <typename Grid, typename PrimitiveSet>
void check_fit_request(const Grid& target, const PrimitiveSet& primitives, double time_limit) {
  if (target.empty() || target.count() == 0) throw std::invalid_argument("no shape found");
  if (primitives.empty()) throw std::invalid_argument("no primitive type allowed");
  if (!(time_limit > 0)) throw std::invalid_argument("the time budget must be positive");
}

/// The point of a budget of `time_limit` seconds from `start` at fraction f of it.
inline std::chrono::steady_clock::time_point at_fraction(
    std::chrono::steady_clock::time_point start, double time_limit, double f) {
  return start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                     std::chrono::duration<double>(f * time_limit));
}

}  // namespace csgfit
