// One radius where the designer drew one: the legs under a table, the rods along a plate's
// edges, the pegs standing on it. A view sees each round primitive from one side, and its radius
// comes out a few per cent off, each differently; the tangent planes the hidden faces align with
// (hidden_extents.h) inherit the error.
#pragma once

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// `graph` with the radii of its unconjectured cylinders and spheres that lie close together
/// (sorted, each within 20 % of the next, the group within 1.5x, at least three of them) made
/// equal to the group's median: each member's centre moves by the change of radius in the
/// direction that keeps it closest to what the views saw, and the change is kept when the views
/// do not see the difference (within a quarter of the size weight `k`). Nothing changes when the
/// evidence has no hidden points (a scan without a camera). Deterministic.
PrecedenceGraph equal_radii(PrecedenceGraph graph, const RangeEvidence& evidence, double k);

}  // namespace csgfit
