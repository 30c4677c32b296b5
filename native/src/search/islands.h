// Internal to search/: seed 000's parallel hill climbing, written once. An island is a
// population of candidate trees and the perturbations of one dimension (Operators2D,
// Operators3D); islands run a generation in parallel, then share trees (SearchParams).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "csgfit/search/params.h"
#include "csgfit/search/stats.h"
#include "model/random.h"

namespace csgfit::islands {

using Clock = std::chrono::steady_clock;

/// One island: its own random numbers (inside `ops`) and population.
template <typename Ops>
struct Island {
  using Candidate = typename Ops::Candidate;

  Ops ops;
  std::vector<Candidate> population;
  std::size_t stale = 0;  // perturbations since the last accepted one

  /// One generation: `count` perturbations with hill-climbing acceptance (a child replaces
  /// the member it came from when it scores lower), refocusing every refocus_interval trees.
  void run(std::size_t count, const SearchParams& params, const std::function<bool()>& should_stop) {
    for (std::size_t t = 0; t < count; ++t) {
      if (should_stop()) return;
      const std::size_t i =
          population.size() == 1 ? 0 : rnd::pick(ops.rng(), population.size());
      Candidate child = ops.perturb(population[i]);
      if (child.score < population[i].score - params.accept_margin) {
        ops.accept(child);
        population[i] = std::move(child);
        stale = 0;
      } else {
        ++stale;
      }
      if (params.refocus_interval > 0 &&
          ops.trees % static_cast<std::size_t>(params.refocus_interval) == 0)
        refocus();
    }
  }

  /// Seed 000's refocusing: the better half of the population replaces the worse half.
  void refocus() {
    std::stable_sort(population.begin(), population.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
    const std::size_t half = population.size() / 2;
    for (std::size_t i = 0; i < half; ++i) population[population.size() - 1 - i] = population[i];
  }

  const Candidate& best() const {
    return *std::min_element(population.begin(), population.end(),
                             [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  }
};

/// Runs `work` on every island, one thread each.
/// The island count for `threads` (0: one per hardware thread).
inline int island_count(int threads) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return std::max(1, threads > 0 ? threads : static_cast<int>(hw));
}

/// `count` islands with empty populations over one problem, each with its own random numbers
/// drawn from `seed`: the same seed and count give the same islands.
template <typename Ops, typename Problem>
std::vector<Island<Ops>> make_islands(const Problem& problem, std::uint64_t seed, int count) {
  std::vector<Island<Ops>> isles;
  isles.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const std::uint64_t island_seed =
        rnd::splitmix(seed * 0x100000001b3ULL + static_cast<std::uint64_t>(i));
    isles.push_back(Island<Ops>{Ops(problem, island_seed), {}, 0});
  }
  return isles;
}

template <typename Ops>
void in_parallel(std::vector<Island<Ops>>& isles, const std::function<void(Island<Ops>&)>& work) {
  if (isles.size() == 1) {
    work(isles[0]);
    return;
  }
  std::vector<std::thread> pool;
  for (std::size_t i = 1; i < isles.size(); ++i) pool.emplace_back([&, i] { work(isles[i]); });
  work(isles[0]);
  for (std::thread& t : pool) t.join();
}

/// When and why a search stops: the wall-time limit of the search (which may end before the
/// fit's budget, to leave time for a polish), the caller's cancel flag and progress callback.
struct Limits {
  Clock::time_point start;
  double time_limit = 0;    // the fit's budget, for the progress fraction
  double search_limit = 0;  // when the search itself stops
  const std::atomic<bool>* cancel = nullptr;
  ProgressCallback progress;
};

template <typename Candidate>
struct Outcome {
  Candidate best;
  std::string stop_reason = "converged";
  std::size_t trees = 0;        // perturbations evaluated on all islands
  std::size_t evaluations = 0;  // the islands' tree evaluations
};

/// The islands share trees as SearchParams::migration says.
template <typename Ops>
void migrate(std::vector<Island<Ops>>& isles, const SearchParams& params, std::size_t gen,
             bool improved, std::size_t best_isle, const typename Ops::Candidate& best) {
  using Candidate = typename Ops::Candidate;
  if (isles.size() < 2) return;
  if (params.migration == Migration::RingOfBests) {
    const std::size_t every = static_cast<std::size_t>(std::max(1, params.migration_interval));
    if (gen % every != every - 1) return;
    std::vector<Candidate> bests;
    for (const Island<Ops>& isle : isles) bests.push_back(isle.best());
    for (std::size_t i = 0; i < isles.size(); ++i) {
      auto& pop = isles[i].population;
      auto worst = std::max_element(pop.begin(), pop.end(), [](const Candidate& a, const Candidate& b) {
        return a.score < b.score;
      });
      *worst = bests[(i + 1) % isles.size()];
    }
    return;
  }
  // BestToStuckest: ties go to the lowest index, and never back to the island it came from.
  if (!improved) return;
  std::size_t stuck = best_isle == 0 ? 1 : 0;
  for (std::size_t i = 0; i < isles.size(); ++i)
    if (i != best_isle && isles[i].stale > isles[stuck].stale) stuck = i;
  isles[stuck].population.assign(isles[stuck].population.size(), best);
  isles[stuck].stale = 0;
}

/// Seed 000's search over the islands, from their initial populations: generations of
/// perturbations until the time, the tree budget or max_stale trees without improvement.
/// `best` is the best tree known before the search; `evaluations_before` is added to the
/// progress reports. `on_generation` sees every island before each generation (2D keeps an
/// archive of structures from it).
template <typename Ops>
Outcome<typename Ops::Candidate> search(
    std::vector<Island<Ops>>& isles, typename Ops::Candidate best, const SearchParams& params,
    const Limits& limits, std::size_t evaluations_before,
    const std::function<void(const Island<Ops>&)>& on_generation) {
  using Candidate = typename Ops::Candidate;
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - limits.start).count(); };
  std::atomic<bool> stop_now{false};
  const std::function<bool()> should_stop = [&] {
    if (stop_now.load(std::memory_order_relaxed)) return true;
    if ((limits.cancel && limits.cancel->load(std::memory_order_relaxed)) ||
        elapsed() >= limits.search_limit) {
      stop_now = true;
      return true;
    }
    return false;
  };
  Outcome<Candidate> out;
  std::size_t stale = 0, trees = 0;
  const std::size_t generation = static_cast<std::size_t>(std::max(1, params.generation));
  const std::size_t max_stale = static_cast<std::size_t>(std::max(1, params.max_stale));
  for (std::size_t gen = 0;; ++gen) {
    std::size_t total_trees = 0, total_evals = evaluations_before;
    bool improved = false;
    std::size_t best_isle = 0;
    for (std::size_t i = 0; i < isles.size(); ++i) {
      total_trees += isles[i].ops.trees;
      total_evals += isles[i].ops.evaluations;
      if (on_generation) on_generation(isles[i]);
      const Candidate& b = isles[i].best();
      if (b.score < best.score - 1e-9) {
        best = b;
        best_isle = i;
        improved = true;
      }
    }
    stale = improved ? 0 : stale + (total_trees - trees);
    trees = total_trees;
    if (limits.progress) {
      FitProgress p;
      p.seconds = elapsed();
      p.fraction = std::min(1.0, std::max({p.seconds / limits.time_limit,
                                           static_cast<double>(stale) / static_cast<double>(max_stale),
                                           static_cast<double>(trees) / std::max(1, params.max_trees)}));
      p.best_score = best.score;
      p.best_primitives = best.primitives;
      p.evaluations = total_evals;
      if (!limits.progress(p)) stop_now = true;
    }
    // stop_now without a cancel flag or an expired clock means the progress callback said stop.
    if ((limits.cancel && limits.cancel->load()) || (stop_now && elapsed() < limits.search_limit)) {
      out.stop_reason = "cancelled";
      break;
    }
    if (stop_now || elapsed() >= limits.search_limit) {
      out.stop_reason = "time";
      break;
    }
    if (trees >= static_cast<std::size_t>(params.max_trees)) {
      out.stop_reason = "max-trees";
      break;
    }
    if (stale >= max_stale) break;
    migrate(isles, params, gen, improved, best_isle, best);
    in_parallel<Ops>(isles, [&](Island<Ops>& isle) { isle.run(generation, params, should_stop); });
  }
  for (Island<Ops>& isle : isles) {
    if (on_generation) on_generation(isle);
    if (isle.best().score < best.score - params.accept_margin) best = isle.best();
    out.evaluations += isle.ops.evaluations;
    out.trees += isle.ops.trees;
  }
  out.best = std::move(best);
  return out;
}

}  // namespace csgfit::islands
