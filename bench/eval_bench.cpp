// The incremental evaluators (TreeEvaluator, TreeEvaluator3D) beside seed 000's plain
// evaluation, which scan-converts every primitive and combines the whole tree for each score.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "bench_cases.h"

namespace {

using namespace csgfit;
using namespace csgfit::bench;

/// Every move tried (try_leaf) and then accepted (update_leaf) in turn, each scored by both
/// evaluators; the first disagreement is the case's error. A case whose moves all leave the
/// mismatch at zero is an error too: its check would have compared nothing.
template <class D>
std::string check(const Case<D>& c) {
  typename D::Tree tree = c.tree;
  typename D::Evaluator evaluator(c.target, tree);
  typename D::Tree plain = c.tree;
  const auto prims = csgfit::leaves(plain);
  if (!same_counts(evaluator.mismatch(), plain_mismatch<D>(plain, c.target)))
    return "the evaluators disagree on the unperturbed tree";
  std::size_t scoring = 0;
  for (std::size_t k = 0; k < c.moves.size(); ++k) {
    const Move<D>& m = c.moves[k];
    const Mismatch incremental = evaluator.try_leaf(m.leaf, m.prim);
    const typename D::Prim kept = *prims[m.leaf];
    *prims[m.leaf] = m.prim;
    const Mismatch reference = plain_mismatch<D>(plain, c.target);
    *prims[m.leaf] = kept;
    if (!same_counts(incremental, reference))
      return "try_leaf of move " + std::to_string(k) + ": " + describe(incremental) +
             ", plain evaluation: " + describe(reference);
    if (reference.total() != 0) ++scoring;
  }
  if (scoring == 0) return "no move changes the mismatch";
  for (std::size_t k = 0; k < c.moves.size(); ++k) {
    const Move<D>& m = c.moves[k];
    evaluator.leaf(m.leaf) = m.prim;
    const Mismatch incremental = evaluator.update_leaf(m.leaf);
    *prims[m.leaf] = m.prim;
    const Mismatch reference = plain_mismatch<D>(plain, c.target);
    if (!same_counts(incremental, reference))
      return "update_leaf after move " + std::to_string(k) + ": " + describe(incremental) +
             ", plain evaluation: " + describe(reference);
  }
  return {};
}

/// The case of a benchmark's arguments (leaves, size), with its check.
template <class D>
const Case<D>& cached_case(const benchmark::State& state) {
  return cached<Case<D>>(
      state.range(0), state.range(1), [](std::int64_t leaves, std::int64_t size) {
        Case<D> c = make_case<D>(static_cast<std::size_t>(leaves), static_cast<int>(size),
                                 /*seed=*/1000 + static_cast<std::uint64_t>(leaves));
        c.error = check(c);
        return c;
      });
}

template <class D>
bool ready(benchmark::State& state, const Case<D>& c) {
  if (!c.error.empty()) {
    state.SkipWithError(c.error.c_str());
    return false;
  }
  state.counters["depth"] = static_cast<double>(c.tree.depth());
  return true;
}

/// Gives `evaluate` one of the case's moves per iteration, round and round.
template <class D, class Evaluate>
void over_moves(benchmark::State& state, const Case<D>& c, Evaluate&& evaluate) {
  std::size_t k = 0;
  for (auto _ : state) {
    evaluate(c.moves[k]);
    k = k + 1 == c.moves.size() ? 0 : k + 1;
  }
}

/// The incremental evaluator on the moves the local optimiser makes: with kKeep false a move it
/// considers (try_leaf scores it and changes nothing), with kKeep true one it keeps (the leaf
/// changes and update_leaf recombines its path).
template <class D, bool kKeep>
void incremental(benchmark::State& state) {
  const Case<D>& c = cached_case<D>(state);
  if (!ready(state, c)) return;
  typename D::Tree tree = c.tree;
  typename D::Evaluator evaluator(c.target, tree);
  over_moves(state, c, [&](const Move<D>& m) {
    if constexpr (kKeep) {
      evaluator.leaf(m.leaf) = m.prim;
      benchmark::DoNotOptimize(evaluator.update_leaf(m.leaf));
    } else {
      benchmark::DoNotOptimize(evaluator.try_leaf(m.leaf, m.prim));
    }
  });
}

/// The plain evaluator keeps no state, so scoring a tried move and an accepted one is the same
/// work: one benchmark is the baseline of both.
template <class D>
void plain(benchmark::State& state) {
  const Case<D>& c = cached_case<D>(state);
  if (!ready(state, c)) return;
  typename D::Tree tree = c.tree;
  const auto prims = csgfit::leaves(tree);
  over_moves(state, c, [&](const Move<D>& m) {
    const typename D::Prim kept = *prims[m.leaf];
    *prims[m.leaf] = m.prim;
    benchmark::DoNotOptimize(plain_mismatch<D>(tree, c.target));
    *prims[m.leaf] = kept;
  });
}

void Eval2D_IncrementalTry(benchmark::State& state) { incremental<Flat, false>(state); }
void Eval2D_IncrementalUpdate(benchmark::State& state) { incremental<Flat, true>(state); }
void Eval2D_Plain(benchmark::State& state) { plain<Flat>(state); }
void Eval3D_IncrementalTry(benchmark::State& state) { incremental<Solid, false>(state); }
void Eval3D_IncrementalUpdate(benchmark::State& state) { incremental<Solid, true>(state); }
void Eval3D_Plain(benchmark::State& state) { plain<Solid>(state); }

void cases_2d(benchmark::internal::Benchmark* b) {
  b->ArgNames({"leaves", "size"})->ArgsProduct({{4, 16, 64}, {128, 512}});
  b->Unit(benchmark::kMicrosecond);
}

void cases_3d(benchmark::internal::Benchmark* b) {
  b->ArgNames({"leaves", "size"})->ArgsProduct({{4, 16, 64}, {64, 128}});
  b->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK(Eval2D_IncrementalTry)->Apply(cases_2d);
BENCHMARK(Eval2D_IncrementalUpdate)->Apply(cases_2d);
BENCHMARK(Eval2D_Plain)->Apply(cases_2d);
BENCHMARK(Eval3D_IncrementalTry)->Apply(cases_3d);
BENCHMARK(Eval3D_IncrementalUpdate)->Apply(cases_3d);
BENCHMARK(Eval3D_Plain)->Apply(cases_3d);
