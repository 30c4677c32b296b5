// Internal to pipeline/: the checks every fit makes of what it is asked before it starts.
#pragma once

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

}  // namespace csgfit
