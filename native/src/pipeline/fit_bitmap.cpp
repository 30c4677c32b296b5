// Seed 000's parallel hill climbing, seeded with seed 003's tree.
#include "csgfit/pipeline/fit_bitmap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/features/features2d.h"
#include "csgfit/optimise/prune.h"
#include "csgfit/optimise/snap2d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/seed/decompose2d.h"
#include "csgfit/seed/greedy2d.h"
#include "model/random.h"

namespace csgfit {

double default_k(int width, int height) {
  return 25.0 * static_cast<double>(width) * static_cast<double>(height) / (128.0 * 128.0);
}

namespace {

using Clock = std::chrono::steady_clock;
using rnd::normal;
using rnd::norm_count;
using rnd::pick;
using rnd::Rng;
using rnd::splitmix;
using rnd::uniform;

struct Candidate {
  Node tree;
  Mismatch mismatch;
  std::size_t primitives = 0;
  double score = 0;
};

std::vector<PrimitiveKind> kinds_of(PrimitiveSet set) {
  std::vector<PrimitiveKind> out;
  for (PrimitiveKind k : {PrimitiveKind::Rectangle, PrimitiveKind::Circle, PrimitiveKind::Ellipse,
                          PrimitiveKind::Triangle})
    if (set.has(k)) out.push_back(k);
  return out;
}

// Everything one search shares between its islands (read-only while they run).
struct Problem {
  const Bitmap* target = nullptr;
  double k = 25;
  SearchParams params;
  std::vector<PrimitiveKind> kinds;
  std::vector<DistancePeak> shape_peaks;       // of the target: where ADD puts unions
  std::vector<DistancePeak> background_peaks;  // of the complement: where ADD puts cuts
  LocalOptOptions new_leaf_opt, all_leaf_opt;
};

class Island {
 public:
  Island(const Problem& problem, std::uint64_t seed) : pb_(problem), rng_(seed) {}

  std::vector<Candidate> population;
  std::size_t trees = 0;
  std::size_t evaluations = 0;

  Candidate evaluate(Node tree, const std::vector<Primitive>& fresh) {
    Candidate c;
    if (!simplify(tree)) {
      c.score = std::numeric_limits<double>::infinity();
      return c;
    }
    {
      TreeEvaluator ev(*pb_.target, tree);
      std::vector<std::size_t> fresh_idx;
      for (std::size_t i = 0; i < ev.leaf_count() && !fresh.empty(); ++i)
        if (std::find(fresh.begin(), fresh.end(), ev.leaf(i)) != fresh.end()) fresh_idx.push_back(i);
      if (!fresh_idx.empty()) optimize_leaves(ev, pb_.new_leaf_opt, fresh_idx);
      optimize_leaves(ev, pb_.all_leaf_opt);
      evaluations += ev.evaluations();
    }
    prune(tree, *pb_.target, pb_.k);
    TreeEvaluator ev(*pb_.target, tree);
    evaluations += ev.evaluations() + tree.primitive_count();
    c.mismatch = ev.mismatch();
    c.primitives = tree.primitive_count();
    c.score = score(c.mismatch, c.primitives, pb_.k);
    c.tree = std::move(tree);
    return c;
  }

  Primitive random_primitive(double cx, double cy, double size) {
    const PrimitiveKind kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
    const double w = std::max(1.0, size), h = std::max(1.0, normal(rng_, size, size / 2));
    const double angle = uniform(rng_, 0, 360);
    switch (kind) {
      case PrimitiveKind::Rectangle: return Primitive::rectangle(cx, cy, w, h, angle);
      case PrimitiveKind::Circle: return Primitive::circle(cx, cy, w / 2);
      case PrimitiveKind::Ellipse: return Primitive::ellipse(cx, cy, w / 2, h / 2, angle);
      case PrimitiveKind::Triangle:
        return Primitive::triangle(cx, cy, w, h, angle, std::round(uniform(rng_, -1, 1)));
    }
    return Primitive::rectangle(cx, cy, w, h, angle);
  }

  // Seed 000's random subtree: uniform positions in the middle half, random operators.
  Node random_subtree(int count, std::vector<Primitive>& fresh) {
    const double W = pb_.target->width(), H = pb_.target->height();
    Node tree;
    for (int i = 0; i < count; ++i) {
      const Primitive p = random_primitive(uniform(rng_, W / 4, 3 * W / 4),
                                           uniform(rng_, H / 4, 3 * H / 4),
                                           uniform(rng_, 1, std::min(W, H) / 2));
      fresh.push_back(p);
      if (i == 0) {
        tree = Node::leaf(p);
        continue;
      }
      static const NodeKind ops[3] = {NodeKind::Union, NodeKind::Difference, NodeKind::Intersection};
      tree = Node::op(ops[pick(rng_, 3)], {std::move(tree), Node::leaf(p)});
    }
    return tree;
  }

  // ADD: a small subtree at maxima of a distance map, unioned with or subtracted from a subtree.
  bool add_targeted(Node& tree, std::vector<Primitive>& fresh) {
    const bool as_union = rng_() & 1;
    const std::vector<DistancePeak>& peaks = as_union ? pb_.shape_peaks : pb_.background_peaks;
    if (peaks.empty()) return false;
    const int count = norm_count(rng_, pb_.params.added_size_mean, pb_.params.added_size_sd);
    Node added;
    for (int i = 0; i < count; ++i) {
      // Bigger peaks first, but any of them may be chosen.
      const std::size_t j = std::min(pick(rng_, peaks.size()), pick(rng_, peaks.size()));
      const DistancePeak& pk = peaks[j];
      const double d = pk.distance;
      const Primitive p = random_primitive(pk.x, pk.y, 2 * std::max(1.0, normal(rng_, d, d / 2)));
      fresh.push_back(p);
      added = (i == 0) ? Node::leaf(p) : Node::op(NodeKind::Union, {std::move(added), Node::leaf(p)});
    }
    const std::size_t n = tree.node_count();
    Node* at = (rng_() % 2 == 0) ? &tree : node_at(tree, pick(rng_, n));
    Node old = std::move(*at);
    *at = Node::op(as_union ? NodeKind::Union : NodeKind::Difference, {std::move(old), std::move(added)});
    return true;
  }

  Candidate perturb(const Candidate& parent) {
    Node tree = parent.tree;
    std::vector<Primitive> fresh;
    const SearchParams& sp = pb_.params;
    const double total = sp.p_rep + sp.p_add + sp.p_cut + sp.p_mod;
    double r = uniform(rng_, 0, total);
    const std::size_t n = tree.node_count();
    bool done = false;
    if (r < sp.p_add) {
      done = add_targeted(tree, fresh);
    } else if ((r -= sp.p_add) < sp.p_cut) {
      if (n > 1) {
        const std::size_t idx = 1 + pick(rng_, n - 1);
        // Find the parent of the node at idx and erase that child.
        std::size_t counter = 0;
        std::function<bool(Node&)> cut = [&](Node& node) -> bool {
          ++counter;
          for (std::size_t c = 0; c < node.children.size(); ++c) {
            if (counter == idx) {
              node.children.erase(node.children.begin() + static_cast<std::ptrdiff_t>(c));
              return true;
            }
            if (cut(node.children[c])) return true;
          }
          return false;
        };
        done = cut(tree);
      }
    } else if ((r -= sp.p_cut) < sp.p_mod) {
      std::vector<Primitive*> ls = leaves(tree);
      Primitive* p = ls[pick(rng_, ls.size())];
      if (pb_.kinds.size() > 1) {
        PrimitiveKind kind;
        do kind = pb_.kinds[pick(rng_, pb_.kinds.size())];
        while (kind == p->kind);
        p->kind = kind;
        if (kind == PrimitiveKind::Triangle) p->apex = std::round(uniform(rng_, -1, 1));
        p->normalize();
        fresh.push_back(*p);
        done = true;
      }
    }
    if (!done) {
      // REP (also the fallback when another operator had nothing to act on).
      Node* at = node_at(tree, pick(rng_, n));
      const int e = static_cast<int>(at->primitive_count());
      *at = random_subtree(norm_count(rng_, e, sp.added_size_sd), fresh);
    }
    ++trees;
    return evaluate(std::move(tree), fresh);
  }

  // One generation: `count` perturbations with hill-climbing acceptance, refocusing every n.
  void run(std::size_t count, const std::function<bool()>& should_stop) {
    for (std::size_t t = 0; t < count; ++t) {
      if (should_stop()) return;
      const std::size_t i = pick(rng_, population.size());
      Candidate child = perturb(population[i]);
      if (child.score < population[i].score) population[i] = std::move(child);
      if (trees % static_cast<std::size_t>(std::max(1, pb_.params.refocus_interval)) == 0) refocus();
    }
  }

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

  Rng& rng() { return rng_; }

 private:
  const Problem& pb_;
  Rng rng_;
};

FitStats stats_of(const Candidate& c, const Bitmap& target, double k) {
  FitStats s;
  s.k = k;
  s.score = c.score;
  s.excess = c.mismatch.excess;
  s.uncovered = c.mismatch.uncovered;
  s.primitives = c.primitives;
  const double tc = static_cast<double>(target.count());
  const double inter = tc - static_cast<double>(c.mismatch.uncovered);
  const double uni = tc + static_cast<double>(c.mismatch.excess);
  s.iou = uni > 0 ? inter / uni : 1.0;
  return s;
}

}  // namespace

FitResult fit_bitmap(const Bitmap& target, const FitOptions& options,
                     const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  const auto start = Clock::now();
  if (target.empty() || target.count() == 0) throw std::invalid_argument("no shape found");
  if (options.primitives.empty()) throw std::invalid_argument("no primitive type allowed");
  if (!(options.time_limit > 0)) throw std::invalid_argument("the time budget must be positive");

  Problem pb;
  pb.target = &target;
  pb.k = options.k >= 0 ? options.k : default_k(target.width(), target.height());
  pb.params = options.search;
  pb.kinds = kinds_of(options.primitives);
  pb.new_leaf_opt.max_sweeps = pb.params.local_iterations;
  pb.new_leaf_opt.initial_step = 2.0;
  pb.new_leaf_opt.min_step = 0.25;
  pb.all_leaf_opt.max_sweeps = 3;
  pb.all_leaf_opt.initial_step = 0.5;
  pb.all_leaf_opt.min_step = 0.25;
  // --time bounds the wall time: no single tree's optimisation may run past it.
  const auto at_fraction = [&](double f) {
    return start + std::chrono::duration_cast<Clock::duration>(
                       std::chrono::duration<double>(f * options.time_limit));
  };
  pb.new_leaf_opt.deadline = pb.all_leaf_opt.deadline = at_fraction(1.0);
  pb.shape_peaks = distance_peaks(target, 1.0, 64);
  pb.background_peaks = distance_peaks(target.inverted(), 1.0, 64);

  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int threads = options.threads > 0 ? options.threads : static_cast<int>(hw);
  const int islands = std::max(1, std::min(threads, std::max(1, pb.params.population)));
  const int per_island = std::max(2, pb.params.population / islands);

  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  std::atomic<bool> stop_now{false};
  auto should_stop = [&] {
    if (stop_now.load(std::memory_order_relaxed)) return true;
    if ((cancel && cancel->load(std::memory_order_relaxed)) || elapsed() >= options.time_limit) {
      stop_now = true;
      return true;
    }
    return false;
  };

  // The first tree: seed 003, locally optimised and pruned.
  std::vector<Island> isles;
  isles.reserve(static_cast<std::size_t>(islands));
  for (int i = 0; i < islands; ++i)
    isles.emplace_back(pb, splitmix(options.seed * 0x100000001b3ULL + static_cast<std::uint64_t>(i)));
  std::size_t evaluations = 0;
  Candidate seed_candidate;
  const bool can_decompose = options.primitives.has(PrimitiveKind::Rectangle);
  if (pb.params.seed_with_decomposition && can_decompose) {
    DecomposeOptions dopt;
    dopt.primitives = options.primitives;
    dopt.k = pb.k;
    Node seed_tree = decompose(target, dopt);
    LocalOptOptions polish;
    polish.max_sweeps = pb.params.local_iterations;
    polish.initial_step = 1.0;
    polish.min_step = 0.125;
    polish.deadline = at_fraction(0.5);
    {
      TreeEvaluator ev(target, seed_tree);
      optimize_leaves(ev, polish);
      evaluations += ev.evaluations();
    }
    seed_candidate = isles[0].evaluate(std::move(seed_tree), {});
  }
  Candidate greedy_candidate;
  if (pb.params.seed_with_decomposition) {
    GreedyOptions gopt;
    gopt.primitives = options.primitives;
    gopt.k = pb.k;
    greedy_candidate = isles[0].evaluate(greedy_cover(target, gopt), {});
  }

  // Initial populations: the seed tree where there is one, random trees (seed 000) otherwise.
  // Built in parallel, one island per thread, each with its own generator.
  auto parallel = [&](const std::function<void(Island&)>& work) {
    if (islands == 1) {
      work(isles[0]);
      return;
    }
    std::vector<std::thread> pool;
    for (int i = 1; i < islands; ++i) pool.emplace_back([&, i] { work(isles[static_cast<std::size_t>(i)]); });
    work(isles[0]);
    for (std::thread& t : pool) t.join();
  };
  parallel([&](Island& isle) {
    for (int j = 0; j < per_island; ++j) {
      // Alternate the two deterministic seeds (seed 003's and the greedy cover).
      const Candidate& seeded = (j % 2 == 0 && seed_candidate.primitives > 0) ? seed_candidate : greedy_candidate;
      if (seeded.primitives > 0) {
        isle.population.push_back(seeded);
        continue;
      }
      if (should_stop() && !isle.population.empty()) {
        isle.population.push_back(isle.population.front());
        continue;
      }
      std::vector<Primitive> fresh;
      const int count = norm_count(isle.rng(), pb.params.initial_size_mean, pb.params.initial_size_sd);
      Node t = isle.random_subtree(count, fresh);
      isle.population.push_back(isle.evaluate(std::move(t), fresh));
      ++isle.trees;
    }
  });

  // Archive of the best tree per structure, for the alternatives.
  std::map<std::string, Candidate> archive;
  auto remember = [&](const Candidate& c) {
    if (!std::isfinite(c.score)) return;
    const std::string key = structure_string(c.tree);
    auto it = archive.find(key);
    if (it == archive.end() || c.score < it->second.score) archive[key] = c;
  };

  Candidate best;
  best.score = std::numeric_limits<double>::infinity();
  std::size_t stale = 0, trees = 0;
  std::string stop_reason = "converged";
  const std::size_t generation = static_cast<std::size_t>(std::max(1, pb.params.refocus_interval));
  for (std::size_t gen = 0;; ++gen) {
    std::size_t total_trees = 0, total_evals = evaluations;
    bool improved = false;
    for (Island& isle : isles) {
      total_trees += isle.trees;
      total_evals += isle.evaluations;
      for (const Candidate& c : isle.population) remember(c);
      const Candidate& b = isle.best();
      if (b.score < best.score - 1e-9) {
        best = b;
        improved = true;
      }
    }
    if (!improved) stale += total_trees - trees;
    else stale = 0;
    trees = total_trees;
    if (progress) {
      FitProgress p;
      p.seconds = elapsed();
      p.fraction = std::min(1.0, std::max({p.seconds / options.time_limit,
                                           static_cast<double>(stale) / std::max(1, pb.params.max_stale),
                                           static_cast<double>(trees) / std::max(1, pb.params.max_trees)}));
      p.best_score = best.score;
      p.best_primitives = best.primitives;
      p.evaluations = total_evals;
      if (!progress(p)) stop_now = true;
    }
    // stop_now without a cancel flag or an expired clock means the progress callback said stop.
    const bool cancelled = (cancel && cancel->load()) || (stop_now && elapsed() < options.time_limit);
    if (cancelled) {
      stop_reason = "cancelled";
      break;
    }
    if (stop_now || elapsed() >= options.time_limit) {
      stop_reason = "time";
      break;
    }
    if (trees >= static_cast<std::size_t>(pb.params.max_trees)) {
      stop_reason = "max-trees";
      break;
    }
    if (stale >= static_cast<std::size_t>(pb.params.max_stale)) {
      stop_reason = "converged";
      break;
    }
    // Migration every fourth generation: each island receives its neighbour's best.
    if (islands > 1 && gen % 4 == 3) {
      std::vector<Candidate> bests;
      for (const Island& isle : isles) bests.push_back(isle.best());
      for (int i = 0; i < islands; ++i) {
        Island& isle = isles[static_cast<std::size_t>(i)];
        auto worst = std::max_element(isle.population.begin(), isle.population.end(),
                                      [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
        *worst = bests[static_cast<std::size_t>((i + 1) % islands)];
      }
    }
    parallel([&](Island& isle) { isle.run(generation, should_stop); });
  }
  for (Island& isle : isles) {
    for (const Candidate& c : isle.population) remember(c);
    if (isle.best().score < best.score) best = isle.best();
    evaluations += isle.evaluations;
  }
  std::size_t all_trees = 0;
  for (const Island& isle : isles) all_trees += isle.trees;

  // Final polish of the winner at sub-pixel steps.
  {
    LocalOptOptions polish;
    polish.max_sweeps = pb.params.local_iterations;
    polish.initial_step = 0.5;
    polish.min_step = 1.0 / 32;
    polish.deadline = at_fraction(1.05);  // a little grace: it makes the numbers clean
    Node tree = best.tree;
    {
      TreeEvaluator ev(target, tree);
      optimize_leaves(ev, polish);
      evaluations += ev.evaluations();
    }
    prune(tree, target, pb.k);
    TreeEvaluator ev(target, tree);
    // Designer-friendly numbers for at most 0.2 % of the shape's pixels (and never more than
    // one primitive's worth of score).
    const double snap_budget = std::min(pb.k, 0.002 * static_cast<double>(target.count()));
    snap_to_design_values(ev, options.primitives, snap_budget);
    evaluations += ev.evaluations();
    Candidate polished{tree, ev.mismatch(), tree.primitive_count(), 0};
    polished.score = score(polished.mismatch, polished.primitives, pb.k);
    // Snapping may cost a little score; it is kept when the tree is otherwise no worse.
    if (polished.score <= best.score + snap_budget) best = polished;
  }
  {
    TreeEvaluator ev(target, best.tree);
    untie(ev);
  }

  FitResult result;
  result.width = target.width();
  result.height = target.height();
  result.tree = best.tree;
  result.stats = stats_of(best, target, pb.k);
  result.stats.evaluations = evaluations;
  result.stats.trees = all_trees;
  result.stats.seconds = elapsed();
  result.stats.stop_reason = stop_reason;

  if (options.alternatives > 0) {
    const std::string best_key = structure_string(best.tree);
    std::vector<const Candidate*> ranked;
    for (const auto& [key, c] : archive)
      if (key != best_key) ranked.push_back(&c);
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const Candidate* a, const Candidate* b) { return a->score < b->score; });
    for (const Candidate* c : ranked) {
      if (result.alternatives.size() >= static_cast<std::size_t>(options.alternatives)) break;
      FitTree alt{c->tree, stats_of(*c, target, pb.k)};
      result.alternatives.push_back(std::move(alt));
    }
  }
  return result;
}

}  // namespace csgfit
