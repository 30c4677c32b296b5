// Internal to pipeline/: what every fit shares before and while it runs: the checks of what it
// is asked, and the points of its time budget.
#pragma once

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "csgfit/pipeline/option_limits.h"

namespace csgfit {

/// Throws std::invalid_argument (the fits' contract for bad options) for a budget, thread
/// count or size weight outside option_rules; a negative k is the contract's "default for the
/// input's size", NaN is not.
inline void check_search_options(double time_limit, int threads, double k) {
  const auto check = [](const char* name, double value, const NumberRule& rule) {
    const std::string why = rule_violation(rule, value);
    if (!why.empty()) throw std::invalid_argument(std::string(name) + " " + why);
  };
  check("time", time_limit, option_rules::time);
  check("threads", threads, option_rules::threads);
  if (std::isnan(k) || k >= 0) check("k", k, option_rules::k);
}

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
