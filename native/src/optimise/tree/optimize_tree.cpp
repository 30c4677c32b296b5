#include "csgfit/optimise/optimize_tree.h"

#include <chrono>

#include "csgfit/error.h"
#include "csgfit/optimise/redundancy.h"
#include "csgfit/optimise/structural_rules.h"
#include "stages.h"

namespace csgfit::opt {

RemainingMethod remaining_method_from_string(const std::string& name) {
  if (name == "auto") return RemainingMethod::Auto;
  if (name == "espresso") return RemainingMethod::Espresso;
  if (name == "qmc") return RemainingMethod::QuineMcCluskey;
  if (name == "setcover") return RemainingMethod::SetCover;
  if (name == "ga") return RemainingMethod::Genetic;
  throw InputError("unknown --method '" + name + "' (auto, espresso, qmc, setcover, ga)");
}

std::string to_string(RemainingMethod method) {
  switch (method) {
    case RemainingMethod::Auto: return "auto";
    case RemainingMethod::Espresso: return "espresso";
    case RemainingMethod::QuineMcCluskey: return "qmc";
    case RemainingMethod::SetCover: return "setcover";
    case RemainingMethod::Genetic: return "ga";
  }
  return "?";
}

namespace {

// A two-level cover or a GA tree is free on the canonical intersection terms that no sample
// saw; it replaces the remaining solid only when a second, independent sample set agrees.
template <std::size_t D>
RemainingSolver<D> remaining_solver(const OptimizeOptions& options, const SampleSet<D>& validation,
                                    OptimizeReport& report) {
  return [&options, &validation, &report](const Expr& solid, const SampleSet<D>& s) {
    Expr best = options.method == RemainingMethod::Genetic
                    ? genetic_remaining(solid, s, options, report.pareto)
                    : minimise_two_level(solid, s, options.method, options.seed);
    if (expression_size(best) < expression_size(solid) && validation.evaluate(best) == validation.evaluate(solid)) {
      ++report.remaining_improved;
      return best;
    }
    return solid;
  };
}

// The seed's stages on a solid without opaque leaves.
template <std::size_t D>
Expr optimise_solid(Expr e, const SampleSet<D>& s, const SampleSet<D>& validation, const OptimizeOptions& options,
                    OptimizeReport& report) {
  if (!e.is_operator()) return e;
  const RemainingSolver<D> remaining = remaining_solver<D>(options, validation, report);
  Expr decomposed = options.decompose ? decompose_dominant(e, s, remaining, report) : remaining(e, s);
  const RedundancyReport r = remove_redundancy(decomposed, s);
  report.structural_rewrites += r.structural;
  report.sampled_removals += r.sampled;
  return expression_size(decomposed) < expression_size(e) ? decomposed : e;
}

// Every largest subtree free of opaque leaves is optimised on its own; the operators above
// opaque leaves keep their place.
template <std::size_t D>
Expr optimise_around_opaque(Expr e, const SampleSet<D>& s, const SampleSet<D>& validation,
                            const OptimizeOptions& options, OptimizeReport& report) {
  if (!has_opaque(e)) return optimise_solid(std::move(e), s, validation, options, report);
  for (Expr& k : e.kids) k = optimise_around_opaque(std::move(k), s, validation, options, report);
  return e;
}

std::size_t count_opaque(const Expr& e) {
  std::size_t n = e.op == ExprOp::Opaque;
  for (const Expr& k : e.kids) n += count_opaque(k);
  return n;
}

// Counts the fresh samples on which the two trees disagree.
template <std::size_t D>
std::size_t mismatches(const Expr& a, const Expr& b, const SampleSet<D>& check) {
  const Column ca = check.evaluate(a), cb = check.evaluate(b);
  std::size_t n = 0;
  for (std::size_t w = 0; w < ca.size(); ++w) n += static_cast<std::size_t>(__builtin_popcountll(ca[w] ^ cb[w]));
  return n;
}

}  // namespace

template <std::size_t D>
OptimizeResult optimize_tree(const Expr& tree, const HalfspaceList<D>& halfspaces, const OptimizeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  OptimizeResult result;
  OptimizeReport& report = result.report;
  report.size_before = expression_size(tree);
  report.halfspaces_before = halfspaces_used(tree).size();
  report.opaque = count_opaque(tree);
  if (halfspaces.empty()) {
    result.tree = tree;
    report.size_after = report.size_before;
    return result;
  }
  const SampleSet<D> samples(halfspaces, {options.seed, options.finest, 0});
  const bool sampled = !has_opaque(tree);
  if (sampled && samples.is_empty(tree)) throw InputError("the tree is empty: it has no inside anywhere");
  report.proximity_before = proximity(tree, samples);

  Expr e = tree;
  const RedundancyReport first = remove_redundancy(e, samples);
  report.structural_rewrites += first.structural;
  report.sampled_removals += first.sampled;
  report.stage_sizes.push_back({"redundancy removal", expression_size(e)});
  Expr after_rules = e;  // what the check falls back to before the input itself
  if (!eliminate_complements(after_rules)) after_rules = tree;
  const SampleSet<D> validation(halfspaces, {options.seed ^ 0xa11d0e5ULL, options.finest, 0});
  e = optimise_around_opaque(std::move(e), samples, validation, options, report);
  report.stage_sizes.push_back({"decomposition and remaining solid", expression_size(e)});
  if (!eliminate_complements(e)) throw InputError("the tree is unbounded (a complement at its root)");
  remove_redundancy(e, samples);
  report.stage_sizes.push_back({"redundancy removal again", expression_size(e)});

  if (sampled) {  // the same solid on samples the optimiser never saw
    const SampleSet<D> check(halfspaces, {options.seed ^ 0x5eedc0ffeeULL, options.finest, 0});
    report.check_points = check.point_count();
    report.check_mismatches = mismatches(tree, e, check);
    if (report.check_mismatches > 0) {  // the last stage that passes, else the input
      report.reverted = true;
      e = mismatches(tree, after_rules, check) == 0 ? after_rules : tree;
      apply_structural_rules(e);
      eliminate_complements(e);
    }
  }
  report.empty_decisions = samples.decisions();
  report.cache_hits = samples.cache_hits();
  report.proximity_after = proximity(e, samples);
  report.size_after = expression_size(e);
  report.halfspaces_after = halfspaces_used(e).size();
  result.tree = std::move(e);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

template OptimizeResult optimize_tree<2>(const Expr&, const HalfspaceList<2>&, const OptimizeOptions&);
template OptimizeResult optimize_tree<3>(const Expr&, const HalfspaceList<3>&, const OptimizeOptions&);

}  // namespace csgfit::opt
