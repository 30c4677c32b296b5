// The rewriting rules of seed 001's redundancy removal that need no geometry, applied bottom
// up until none applies: empty and universal set propagation, double complement, flattening,
// identical operands (syntactically), absorption and factoring by the distributive law.
#pragma once

#include "csgfit/optimise/expression.h"

namespace csgfit::opt {

/// Rewrites `e` into an equal expression (the same solid for any geometry of its leaves) that
/// is never larger; returns how many rewrites were made.
std::size_t apply_structural_rules(Expr& e);

}  // namespace csgfit::opt
