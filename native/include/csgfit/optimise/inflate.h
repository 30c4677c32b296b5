// Seed 001's redundancy generator (Sec. 6.1): a tree made larger without changing its solid,
// by copied subtree insertion (CSI), double negation (DNI), the distributive law (DLI) and the
// absorption law (ALI) at random places. The benchmarks and tests inflate real programs and
// check that the optimiser brings them back.
#pragma once

#include <array>
#include <cstdint>

#include "csgfit/optimise/expression.h"

namespace csgfit::opt {

struct InflateOptions {
  std::size_t steps = 10;                                 ///< the seed's i
  std::array<double, 4> weights{1, 1, 1, 1};              ///< CSI, DNI, DLI, ALI probabilities
  std::uint64_t seed = 1;
  std::size_t max_size = 100000;                          ///< a step that would pass it is skipped
};

struct InflateReport {
  std::array<std::size_t, 4> applied{};  ///< steps of each kind that changed the tree
};

/// The inflated tree: the same solid for any geometry of the leaves. The seed's GRI (the GA
/// run backwards) is not among the strategies.
Expr inflate(const Expr& tree, const InflateOptions& options, InflateReport* report = nullptr);

}  // namespace csgfit::opt
