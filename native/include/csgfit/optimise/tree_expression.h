// Our own trees (CsgNode over 2D or 3D primitives) as the optimiser's expressions and back,
// and the optimiser as the last stage of a fit.
#pragma once

#include "csgfit/model/primitive2d.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree.h"
#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/halfspace.h"
#include "csgfit/optimise/optimize_tree.h"

namespace csgfit::opt {

/// The tree as an expression whose halfspace i is `leaves[i]` (filled here, in pre-order;
/// equal primitives share one index).
template <typename P>
Expr expression_of(const CsgNode<P>& tree, std::vector<P>& leaves);

/// The expression (no complement, opaque or constant left) as a tree over `leaves`.
template <typename P>
CsgNode<P> tree_of(const Expr& e, const std::vector<P>& leaves);

HalfspaceList<2> halfspaces_of(const std::vector<Primitive>& leaves);
HalfspaceList<3> halfspaces_of(const std::vector<Primitive3D>& leaves);

/// Optimises one of our trees; `report` (optional) receives what the optimiser did.
template <typename P>
CsgNode<P> optimize_csg_tree(const CsgNode<P>& tree, const OptimizeOptions& options,
                             OptimizeReport* report = nullptr);

}  // namespace csgfit::opt
