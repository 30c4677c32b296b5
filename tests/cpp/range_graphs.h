// Precedence graphs and evidence for the tests of the range search: a known tree seen by one
// camera above it, and graphs put together from signed primitives.
#pragma once

#include <vector>

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"
#include "range_scans.h"

namespace csgfit::testing {

/// A plate 8 x 6 x 1.5 centred at the origin (top at z = 0.75): the part under the tests' view.
inline const Primitive3D kPlate = Primitive3D::box(0, 0, 0, 8, 6, 1.5);

inline SignedPrimitive signed_node(const Primitive3D& p, bool positive) {
  SignedPrimitive s;
  s.primitive = p;
  s.positive = positive;
  return s;
}

/// Each of `positives` a subobject of its own.
inline PrecedenceGraph graph_of(const std::vector<SignedPrimitive>& positives) {
  PrecedenceGraph g;
  for (const SignedPrimitive& p : positives) g = with_node(g, p, {});
  return g;
}

/// The evidence of `truth` seen from azimuth 30, elevation 35 degrees (its underside hidden).
inline RangeEvidence evidence_of(const Node3D& truth) {
  const RangeScan scan = scan_of(truth, looking_at({0, 0, 0}, 30, 35, 30, 160, 0.08));
  return gather_evidence({scan}, 0.1, 6000);
}

}  // namespace csgfit::testing
