// CLI11 validators made of the solver's option rules (csgfit/pipeline/option_limits.h), so that
// every numeric option is refused at parse time, before any work, with one short line.
#pragma once

#include <CLI/CLI.hpp>

#include "csgfit/pipeline/option_limits.h"

namespace csgfit::cli {

/// Holds an option's value to `rule` ("--time: must be a time in seconds in (0, 1e+06], not -1").
CLI::Validator obeys(const NumberRule& rule);

/// A seed: decimal digits, 0 .. 2^64 - 1 (CLI11 would wrap "-1" around).
CLI::Validator seed_check();

/// Registers --max-memory on `command`: the budget every large allocation checks.
void add_memory_option(CLI::App& command);

}  // namespace csgfit::cli
