// Internal to pipeline/: the morph's stages after the first trees, written once over the
// dimension (search/morph_dims.h): the pair search over islands, the final polish of each tree
// against its own target with a paired prune, and the primitives seen in one shape only.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <vector>

#include "csgfit/pipeline/fit_morph.h"
#include "csgfit/refine/local_opt.h"
#include "search/islands.h"
#include "search/morph_dims.h"
#include "search/morph_operators.h"

namespace csgfit::morph {

template <typename Dim>
using Isle = islands::Island<PairOperators<Dim>>;

/// Islands whose populations hold `first` (in turn, from a different one on each island) and
/// then seed 000's random pairs where the dimension has them (Dim::random_trees; without them
/// the first pairs repeat); `per_island` members each.
template <typename Dim>
std::vector<Isle<Dim>> first_populations(const PairProblem<Dim>& problem,
                                         const std::vector<PairCandidate<Dim>>& first,
                                         std::uint64_t seed, int count, std::size_t per_island) {
  auto isles = islands::make_islands<PairOperators<Dim>>(problem, seed, count);
  islands::in_parallel<PairOperators<Dim>>(isles, [&](Isle<Dim>& isle) {
    // Island i starts with first[i], so that each first pair leads on some island.
    const std::size_t i = static_cast<std::size_t>(&isle - isles.data());
    for (std::size_t j = 0; j < per_island; ++j) {
      if constexpr (Dim::random_trees) {
        if (j >= first.size()) {
          isle.population.push_back(isle.ops.random_pair());
          continue;
        }
      }
      isle.population.push_back(first[(i + j) % first.size()]);
    }
  });
  return isles;
}

/// Each tree's leaves at fine steps against its own target (the structure stays), then the
/// paired prune; kept when the pair scores no worse. Edges end off pixel centres.
template <typename Dim>
PairCandidate<Dim> polish_pair(PairOperators<Dim>& ops, const PairProblem<Dim>& problem,
                               PairCandidate<Dim> best, const LocalOptOptions& lo) {
  typename Dim::Tree ta = best.a.tree, tb = best.b.tree;
  {
    typename Dim::Evaluator ev(*problem.a->target, ta);
    optimize_leaves(ev, lo);
    ops.evaluations += ev.evaluations();
  }
  {
    typename Dim::Evaluator ev(*problem.b->target, tb);
    optimize_leaves(ev, lo);
    ops.evaluations += ev.evaluations();
  }
  PairCandidate<Dim> polished = ops.scored(std::move(ta), std::move(tb));
  ops.accept(polished);
  PairCandidate<Dim> out = polished.score <= best.score ? polished : best;
  Dim::untie_edges(*problem.a, out.a.tree);
  Dim::untie_edges(*problem.b, out.b.tree);
  return out;
}

/// A leaf that draws nothing in one tree becomes zero-sized at a point of its partner (the
/// other tree's leaf), when that leaves the tree's raster as it was; the flags say where each
/// leaf is seen.
template <typename Dim>
std::vector<MorphLeaf> vanish_unseen(typename Dim::Tree& a, typename Dim::Tree& b,
                                     const PairProblem<Dim>& problem) {
  std::vector<MorphLeaf> seen(a.primitive_count());
  auto vanish = [&](typename Dim::Tree& x, const typename Dim::Tree& y,
                    const typename Dim::Problem& pb, std::size_t i) {
    const auto before = Dim::raster(pb, x);
    typename Dim::Tree trial = x;
    *leaves(trial)[i] = Dim::vanished(*leaves(y)[i]);
    if (Dim::raster(pb, trial) != before) return false;
    x = std::move(trial);
    return true;
  };
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (vanish(a, b, *problem.a, i))
      seen[i].in_a = false;
    else if (vanish(b, a, *problem.b, i))
      seen[i].in_b = false;
  }
  return seen;
}

/// The search's winner as a MorphPair: trees, each one's stats, the leaves seen in one shape.
template <typename Dim, typename Result>
void fill_result(Result& out, PairCandidate<Dim> best, const PairProblem<Dim>& problem,
                 const islands::Outcome<PairCandidate<Dim>>& found, std::size_t evaluations,
                 double seconds) {
  out.leaves = vanish_unseen<Dim>(best.a.tree, best.b.tree, problem);
  out.a = std::move(best.a.tree);
  out.b = std::move(best.b.tree);
  const auto stats = [&](FitStats& s, const typename Dim::Problem& pb, const typename Dim::Tree& t) {
    std::size_t unused = 0;  // a last scoring for the stats, not part of the search
    const typename Dim::Single c = Dim::Ops::scored(pb, t, unused);
    set_mismatch_stats(s, c.mismatch, pb.target->count(), c.primitives, pb.k);
    s.trees = found.trees;
    s.evaluations = evaluations;
    s.seconds = seconds;
    s.stop_reason = found.stop_reason;
  };
  stats(out.stats_a, *problem.a, out.a);
  stats(out.stats_b, *problem.b, out.b);
}

}  // namespace csgfit::morph
