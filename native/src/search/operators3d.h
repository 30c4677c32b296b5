// Internal to search/: the 3D search's candidate trees and perturbations (REP, ADD at the
// residual, CUT, MOD, INT), for the island driver (islands.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/model/primitive3d.h"
#include "csgfit/model/tree3d.h"
#include "csgfit/model/voxel_grid.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/search/params.h"
#include "search/operators.h"

namespace csgfit {

struct Candidate3D {
  Node3D tree;
  Mismatch mismatch;
  std::size_t primitives = 0;
  double score = std::numeric_limits<double>::infinity();
  VoxelGrid result;  // the tree's voxels, for the residual
};

/// Everything one 3D search shares between its islands (read-only while they run).
struct Problem3D {
  const VoxelGrid* target = nullptr;
  double k = 100;
  SearchParams params;
  std::vector<PrimitiveKind3D> kinds;
  PrimitiveSet3D primitives;
  LocalOptOptions new_leaf_opt, all_leaf_opt;
  // Round primitives matched to the whole target: what INT intersects a tree with to trim its
  // outline (a cube intersected with a sphere, a plate with a cylinder).
  std::vector<Primitive3D> hulls;
  // Primitives read off the input's surface, with their sign: what ADD tries beside the
  // residual's match (issue 11: the designer's cylinder, not the boxes that fill its voxels).
  std::vector<search_ops::Proposal<Primitive3D>> proposals;
};

/// One island's perturbations and their random numbers.
class Operators3D : public search_ops::IslandOperators<Problem3D> {
 public:
  using Candidate = Candidate3D;
  using IslandOperators::IslandOperators;

  /// Optimises the fresh leaves (all leaves when polish_all) and scores the tree. Pruning is
  /// left to accept(): most perturbations are rejected, and for those it would be wasted.
  Candidate evaluate(Node3D tree, const std::vector<Primitive3D>& fresh, bool polish_all);
  /// A child of `parent`: one perturbation drawn by the odds, then evaluate().
  Candidate perturb(const Candidate& parent);
  /// Prunes an accepted tree and rescores it.
  void accept(Candidate& c);
  /// `tree` scored as it is (no optimisation), its evaluations added to `evaluations`; a tree
  /// without leaves scores infinity.
  static Candidate scored(const Problem3D& pb, Node3D tree, std::size_t& evaluations);
  /// ADD's new primitive: seed 003's match to the thick part of what `raster` (the tree's
  /// voxels) misses (as_union) or adds; nothing when the residual is thin everywhere.
  std::optional<Primitive3D> residual_match(const VoxelGrid& raster, bool as_union);
  /// INT's new primitive: a round primitive matched to the whole target, a little larger.
  std::optional<Primitive3D> trimming_hull();
  /// MOD's (same place and size) or REP's (a new orientation) new primitive: `p` as another
  /// kind (REP may keep the kind).
  Primitive3D changed_kind(const Primitive3D& p, bool new_orientation);
  /// `p` as `kind` with the same centre, orientation and extents.
  static Primitive3D rekinded(const Primitive3D& p, PrimitiveKind3D kind);

 private:
  // ADD at the residual: the thick part of what the tree gets wrong, matched by seed 003's
  // matcher, unioned with or cut from a subtree.
  bool add(Node3D& tree, const VoxelGrid& raster, std::vector<Primitive3D>& fresh);
  // MOD (same place and size, another kind) or REP (another kind, a new orientation).
  bool change_kind(Node3D& tree, std::vector<Primitive3D>& fresh, bool new_orientation);
  // INT: the tree (or a subtree) intersected with a round primitive matched to the target.
  bool intersect(Node3D& tree, std::vector<Primitive3D>& fresh);
};

}  // namespace csgfit
