// The local optimiser (optimize_leaves, 2D and 3D) pulling a perturbed tree back onto its own
// raster: the polish every candidate tree of the search gets.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>

#include "bench_cases.h"
#include "csgfit/refine/local_opt.h"

namespace {

using namespace csgfit;
using namespace csgfit::bench;

LocalOptOptions default_options(Flat) { return LocalOptOptions{}; }
LocalOptOptions default_options(Solid) { return LocalOptOptions{}; }

/// A case's tree with every leaf moved twice as one step of the optimiser would (fixed seed),
/// the target being the unmoved tree's raster.
template <class D>
struct Polish {
  typename D::Tree start;
  typename D::Grid target;
  std::size_t mismatch_before = 0;
  std::size_t mismatch_after = 0;
  std::size_t accepted = 0;
  std::size_t evaluations = 0;
  std::string error;
};

/// One run outside the timed loop: the optimiser must lower the mismatch, and the evaluator's
/// final mismatch must be the plain evaluation's of the tree it left.
template <class D>
std::string check(Polish<D>& p) {
  typename D::Tree tree = p.start;
  typename D::Evaluator evaluator(p.target, tree);
  p.mismatch_before = evaluator.mismatch().total();
  p.accepted = optimize_leaves(evaluator, default_options(D{}));
  p.evaluations = evaluator.evaluations();
  p.mismatch_after = evaluator.mismatch().total();
  const Mismatch reference = plain_mismatch<D>(tree, p.target);
  if (!same_counts(evaluator.mismatch(), reference))
    return "after optimize_leaves the evaluator says " + describe(evaluator.mismatch()) +
           ", the plain evaluation " + describe(reference);
  if (p.mismatch_after >= p.mismatch_before)
    return "optimize_leaves did not lower the mismatch (" + std::to_string(p.mismatch_before) +
           " -> " + std::to_string(p.mismatch_after) + ")";
  return {};
}

/// The perturbed tree of a benchmark's arguments (leaves, size), with its check.
template <class D>
const Polish<D>& cached_polish(const benchmark::State& state) {
  return cached<Polish<D>>(
      state.range(0), state.range(1), [](std::int64_t leaves, std::int64_t size) {
        const std::uint64_t seed = 2000 + static_cast<std::uint64_t>(leaves);
        Polish<D> p;
        p.start =
            tree_with_leaves<D>(static_cast<std::size_t>(leaves), static_cast<int>(size), seed);
        p.target = D::render(p.start, D::frame(static_cast<int>(size)));
        std::mt19937_64 rng(seed);
        for (auto* prim : csgfit::leaves(p.start)) *prim = D::perturb(rng, D::perturb(rng, *prim));
        p.error = check(p);
        return p;
      });
}

/// Each iteration polishes a fresh copy of the perturbed tree, the evaluator's set-up (one
/// scan conversion per primitive) included, as the search pays it for every candidate.
template <class D>
void polish(benchmark::State& state) {
  const Polish<D>& p = cached_polish<D>(state);
  if (!p.error.empty()) {
    state.SkipWithError(p.error.c_str());
    return;
  }
  for (auto _ : state) {
    typename D::Tree tree = p.start;
    typename D::Evaluator evaluator(p.target, tree);
    benchmark::DoNotOptimize(optimize_leaves(evaluator, default_options(D{})));
  }
  state.counters["accepted"] = static_cast<double>(p.accepted);
  state.counters["evaluations"] = static_cast<double>(p.evaluations);
  state.counters["mismatch_before"] = static_cast<double>(p.mismatch_before);
  state.counters["mismatch_after"] = static_cast<double>(p.mismatch_after);
}

void LocalOpt2D(benchmark::State& state) { polish<Flat>(state); }
void LocalOpt3D(benchmark::State& state) { polish<Solid>(state); }

}  // namespace

BENCHMARK(LocalOpt2D)
    ->ArgNames({"leaves", "size"})
    ->ArgsProduct({{4, 16}, {128, 256}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(LocalOpt3D)
    ->ArgNames({"leaves", "size"})
    ->ArgsProduct({{4, 16}, {64}})
    ->Unit(benchmark::kMillisecond);
