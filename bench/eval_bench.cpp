// The incremental evaluators (TreeEvaluator, TreeEvaluator3D) beside seed 000's plain
// evaluation, which scan-converts every primitive and combines the whole tree for each score.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

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

/// Google Benchmark calls a benchmark function several times while it sizes the iteration
/// count; the case (and its check, a few hundred full renders) is built once and shared by the
/// three benchmarks of the same tree and grid.
template <class D>
const Case<D>& cached_case(const benchmark::State& state) {
  static std::map<std::pair<std::int64_t, std::int64_t>, Case<D>> cases;
  const auto key = std::make_pair(state.range(0), state.range(1));
  auto it = cases.find(key);
  if (it == cases.end()) {
    Case<D> c = make_case<D>(static_cast<std::size_t>(key.first), static_cast<int>(key.second),
                             /*seed=*/1000 + static_cast<std::uint64_t>(key.first));
    c.error = check(c);
    it = cases.emplace(key, std::move(c)).first;
  }
  return it->second;
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

/// A move the local optimiser considers: try_leaf scores it and changes nothing.
template <class D>
void incremental_try(benchmark::State& state) {
  const Case<D>& c = cached_case<D>(state);
  if (!ready(state, c)) return;
  typename D::Tree tree = c.tree;
  typename D::Evaluator evaluator(c.target, tree);
  std::size_t k = 0;
  for (auto _ : state) {
    const Move<D>& m = c.moves[k];
    benchmark::DoNotOptimize(evaluator.try_leaf(m.leaf, m.prim));
    k = k + 1 == c.moves.size() ? 0 : k + 1;
  }
}

/// A move the local optimiser keeps: the leaf changes and update_leaf recombines its path.
template <class D>
void incremental_update(benchmark::State& state) {
  const Case<D>& c = cached_case<D>(state);
  if (!ready(state, c)) return;
  typename D::Tree tree = c.tree;
  typename D::Evaluator evaluator(c.target, tree);
  std::size_t k = 0;
  for (auto _ : state) {
    const Move<D>& m = c.moves[k];
    evaluator.leaf(m.leaf) = m.prim;
    benchmark::DoNotOptimize(evaluator.update_leaf(m.leaf));
    k = k + 1 == c.moves.size() ? 0 : k + 1;
  }
}

/// The plain evaluator keeps no state, so scoring a tried move and an accepted one is the same
/// work: one benchmark is the baseline of both.
template <class D>
void plain(benchmark::State& state) {
  const Case<D>& c = cached_case<D>(state);
  if (!ready(state, c)) return;
  typename D::Tree tree = c.tree;
  const auto prims = csgfit::leaves(tree);
  std::size_t k = 0;
  for (auto _ : state) {
    const Move<D>& m = c.moves[k];
    const typename D::Prim kept = *prims[m.leaf];
    *prims[m.leaf] = m.prim;
    benchmark::DoNotOptimize(plain_mismatch<D>(tree, c.target));
    *prims[m.leaf] = kept;
    k = k + 1 == c.moves.size() ? 0 : k + 1;
  }
}

void Eval2D_IncrementalTry(benchmark::State& state) { incremental_try<Flat>(state); }
void Eval2D_IncrementalUpdate(benchmark::State& state) { incremental_update<Flat>(state); }
void Eval2D_Plain(benchmark::State& state) { plain<Flat>(state); }
void Eval3D_IncrementalTry(benchmark::State& state) { incremental_try<Solid>(state); }
void Eval3D_IncrementalUpdate(benchmark::State& state) { incremental_update<Solid>(state); }
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
