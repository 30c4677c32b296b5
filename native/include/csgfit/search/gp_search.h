// Seed 004's GP/ES hybrid over CSG trees (Sec. 2.5, 3): a genome is a tree whose terminals are
// the analytic primitives and the NURBS terminal, each individual with its own step size per
// terminal (log-normal self-adaptation, es::mutate); variation by terminal mutation, relation,
// delete, insert, replace and subtree exchange; (mu, lambda) or (mu + lambda) selection on
// several islands that swap their best by recombination every few generations.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "csgfit/search/evolution_strategy.h"
#include "csgfit/search/point_fitness.h"
#include "csgfit/search/stats.h"

namespace csgfit {

struct GpParams {
  std::size_t islands = 4;              ///< 1 = one population
  std::size_t mu = 8, lambda = 32;      ///< per island
  es::Selection selection = es::Selection::Plus;
  std::size_t migration_interval = 8;   ///< generations between exchanges
  std::size_t max_generations = 1000000;
  double time_limit = 30;               ///< seconds of wall time
  std::size_t subset = 600;             ///< points per evaluation (each island its own draw)
  PrimitiveSet3D primitives = PrimitiveSet3D::parse("box,sphere,cylinder");
  FitnessWeights weights;
  std::uint64_t seed = 1;
  int threads = 0;                      ///< islands evaluated in parallel; 0 = all cores
};

/// One genome: the tree and one step size per terminal (pre-order), relative to the part's
/// diagonal for lengths and in radians for turns.
struct GpIndividual {
  Node3D tree;
  std::vector<double> sigma;
  double fitness = -std::numeric_limits<double>::infinity();
};

struct GpResult {
  Node3D tree;                          ///< the best over all islands, judged on every point
  FitnessTerms terms;                   ///< its fitness on every point
  std::size_t generations = 0, evaluations = 0;
  std::vector<double> island_best;      ///< each island's best fitness on its subset
  double seconds = 0;
  std::string stop = "time";           ///< "time", "generations", "cancelled"
};

/// Runs the islands from `first` (trees to start from, e.g. detected primitives; may be
/// empty: then each island starts from single terminals at the worst-fitted points). `patch`
/// (optional) is a NURBS terminal fitted to the cloud that insert may add. Deterministic for a
/// seed when it stops on max_generations. Honours cancel and reports progress as the fit
/// commands do (best fitness as `score`).
GpResult run_gp(const PointTarget& target, const GpParams& params, const std::vector<Node3D>& first,
                const Primitive3D* patch, const ProgressCallback& progress = nullptr,
                const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit
