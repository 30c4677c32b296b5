// Internal: seed 004's variation operators over a GpIndividual (Sec. 2.5), and what they share:
// where the tree fits the cloud worst, and the grounding of a tree seen from above.
#pragma once

#include <vector>

#include "csgfit/search/gp_search.h"
#include "model/random.h"

namespace csgfit::gp {

/// What the operators read: the target, the kinds they may create, the patch insert may add.
struct Context {
  const PointTarget* target = nullptr;
  const std::vector<std::size_t>* subset = nullptr;
  PrimitiveSet3D primitives;
  const Primitive3D* patch = nullptr;
  double first_sigma = 0.05;
};

/// Terminal: each terminal's parameters with probability 1 / terminals (at least one), its own
/// step size self-adapted first (es::mutate, one step size per object as in the seed).
void mutate_terminals(GpIndividual& g, const Context& c, rnd::Rng& rng);
/// Relation: one operator becomes another kind.
bool mutate_relation(GpIndividual& g, rnd::Rng& rng);
/// Delete: a random subtree (not the root) is pruned.
bool delete_subtree(GpIndividual& g, rnd::Rng& rng);
/// Insert: a new terminal where the tree fits worst among a few drawn points: added (union)
/// where the tree lacks material there, cut (difference) where it has too much.
bool insert_terminal(GpIndividual& g, const Context& c, rnd::Rng& rng);
/// A first genome of one terminal under a random point of the cloud (the seed starts "with few
/// randomly selected primitives").
Node3D seed_terminal(const Context& c, rnd::Rng& rng);
/// Replace: a terminal becomes another allowed kind of about the same extent.
bool replace_terminal(GpIndividual& g, const Context& c, rnd::Rng& rng);
/// Recombination: a random subtree of `a` replaced by a random subtree of `b`.
GpIndividual exchange_subtrees(const GpIndividual& a, const GpIndividual& b, rnd::Rng& rng);

/// Top scans: every vertical terminal that adds material stands on the floor, every one that
/// cuts is open to the sky, so that the tree is the solid its z-rays see (no undercuts).
void ground(Node3D& tree, const PointTarget& target);
/// Clean-up after variation: simplify, step sizes matched to the terminals; false when the
/// tree became empty.
bool tidy(GpIndividual& g, const Context& c);

}  // namespace csgfit::gp
