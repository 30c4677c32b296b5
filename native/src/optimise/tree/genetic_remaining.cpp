// Seed 001, Sec. 5.3.2: a GA over trees of the remaining solid's halfspaces, scored on one
// sample per canonical intersection term (CIT) inside and outside the solid. The score is
// w_g * geometry + w_p * proximity + w_s * size (seed: 20 / 2 / 2); the exact trees of the
// last population give the Pareto front of size against proximity (the seed's Fig. 9).
#include <algorithm>
#include <chrono>
#include <set>

#include "csgfit/optimise/redundancy.h"
#include "csgfit/optimise/structural_rules.h"
#include "model/random.h"
#include "stages.h"

namespace csgfit::opt {
namespace {

constexpr std::size_t kPopulation = 100, kIterations = 100, kTournament = 2, kStall = 30;
constexpr double kMutation = 0.3, kCrossover = 0.4;

// The CITs as bit columns: bit t of column v = halfspace vars[v] holds CIT t; `inside` = the
// solid holds it.
struct CitTable {
  std::vector<int> vars;
  std::vector<Column> var_columns;
  Column inside;
  std::size_t count = 0;
};

template <std::size_t D>
CitTable cit_table(const Expr& solid, const SampleSet<D>& s) {
  CitTable t;
  t.vars = halfspaces_used(solid);
  const Column in = s.evaluate(solid);
  std::set<std::vector<bool>> seen;
  std::vector<std::vector<bool>> rows;
  std::vector<bool> row_inside;
  for (std::size_t i = 0; i < s.point_count(); ++i) {
    std::vector<bool> row(t.vars.size() + 1);
    for (std::size_t v = 0; v < t.vars.size(); ++v) row[v] = (s.column(t.vars[v])[i / 64] >> (i % 64)) & 1;
    row.back() = (in[i / 64] >> (i % 64)) & 1;
    if (seen.insert(row).second) rows.push_back(row);
  }
  t.count = rows.size();
  const std::size_t words = (t.count + 63) / 64;
  t.var_columns.assign(t.vars.size(), Column(words, 0));
  t.inside.assign(words, 0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t v = 0; v < t.vars.size(); ++v)
      if (rows[r][v]) t.var_columns[v][r / 64] |= 1ULL << (r % 64);
    if (rows[r].back()) t.inside[r / 64] |= 1ULL << (r % 64);
  }
  return t;
}

Column eval_cits(const Expr& e, const CitTable& t) {
  if (e.op == ExprOp::Halfspace) {
    const auto at = std::lower_bound(t.vars.begin(), t.vars.end(), e.index);
    return t.var_columns[static_cast<std::size_t>(at - t.vars.begin())];
  }
  if (e.op == ExprOp::Empty) return Column(t.inside.size(), 0);
  Column acc = eval_cits(e.kids[0], t);
  for (std::size_t k = 1; k < e.kids.size(); ++k) {
    const Column c = eval_cits(e.kids[k], t);
    for (std::size_t w = 0; w < acc.size(); ++w)
      acc[w] = e.op == ExprOp::Union ? acc[w] | c[w] : e.op == ExprOp::Intersection ? acc[w] & c[w] : acc[w] & ~c[w];
  }
  return acc;
}

// The seed's proximity score of a creature: operations whose two operands share a CIT, over
// all nodes.
double creature_proximity(const Expr& e, const CitTable& t, std::size_t& nodes) {
  ++nodes;
  if (e.kids.size() != 2) return e.is_leaf() ? 1.0 : 0.0;
  double score = any_common(eval_cits(e.kids[0], t), eval_cits(e.kids[1], t)) ? 1.0 : 0.0;
  for (const Expr& k : e.kids) score += creature_proximity(k, t, nodes);
  return score;
}

struct Creature {
  Expr tree;
  double geometry = 0, proximity = 0, score = 0;
  std::size_t size = 0;
};

Expr random_tree(const CitTable& t, rnd::Rng& rng, std::size_t max_depth) {
  if (max_depth <= 1 || rnd::uniform(rng, 0, 1) < 0.3)
    return Expr::halfspace(t.vars[rnd::pick(rng, t.vars.size())]);
  static const ExprOp ops[] = {ExprOp::Union, ExprOp::Intersection, ExprOp::Difference};
  return Expr::make(ops[rnd::pick(rng, 3)], {random_tree(t, rng, max_depth - 1), random_tree(t, rng, max_depth - 1)});
}

std::size_t node_total(const Expr& e) {
  std::size_t n = 1;
  for (const Expr& k : e.kids) n += node_total(k);
  return n;
}

Expr* node_by_index(Expr& e, std::size_t& i) {
  if (i == 0) return &e;
  for (Expr& k : e.kids) {
    --i;
    if (Expr* found = node_by_index(k, i)) return found;
  }
  return nullptr;
}

Expr* random_node(Expr& e, rnd::Rng& rng) {
  std::size_t i = rnd::pick(rng, node_total(e));
  return node_by_index(e, i);
}

// The GA works on binary trees, as the seed's: n-ary operators fold left.
Expr binary(const Expr& e) {
  if (e.kids.empty()) return e;
  Expr acc = binary(e.kids[0]);
  for (std::size_t k = 1; k < e.kids.size(); ++k) acc = Expr::make(e.op, {std::move(acc), binary(e.kids[k])});
  return acc;
}

void score_population(std::vector<Creature>& pop, const CitTable& t, const OptimizeOptions& o) {
  std::size_t lo = SIZE_MAX, hi = 0;
  for (Creature& c : pop) {
    const Column in = eval_cits(c.tree, t);
    std::size_t wrong = 0;
    for (std::size_t w = 0; w < in.size(); ++w) wrong += static_cast<std::size_t>(__builtin_popcountll(in[w] ^ t.inside[w]));
    c.geometry = 1.0 - static_cast<double>(wrong) / static_cast<double>(t.count);
    std::size_t nodes = 0;
    c.proximity = creature_proximity(c.tree, t, nodes) / static_cast<double>(nodes);
    c.size = node_total(c.tree);
    lo = std::min(lo, c.size), hi = std::max(hi, c.size);
  }
  for (Creature& c : pop) {
    const double size_score = hi > lo ? 1.0 - static_cast<double>(c.size - lo) / static_cast<double>(hi - lo) : 1.0;
    c.score = o.geometry_weight * c.geometry + o.proximity_weight * c.proximity + o.size_weight * size_score;
  }
}

const Creature& tournament(const std::vector<Creature>& pop, rnd::Rng& rng) {
  const Creature* best = &pop[rnd::pick(rng, pop.size())];
  for (std::size_t k = 1; k < kTournament; ++k) {
    const Creature& c = pop[rnd::pick(rng, pop.size())];
    if (c.score > best->score) best = &c;
  }
  return *best;
}

std::vector<Creature> next_generation(const std::vector<Creature>& pop, const CitTable& t, rnd::Rng& rng,
                                      std::size_t max_depth) {
  std::vector<Creature> next;
  const auto best = std::max_element(pop.begin(), pop.end(), [](auto& a, auto& b) { return a.score < b.score; });
  next.push_back(*best);  // elitism
  while (next.size() < pop.size()) {
    Creature child = tournament(pop, rng);
    if (rnd::uniform(rng, 0, 1) < kCrossover) {
      Expr donor = tournament(pop, rng).tree;
      *random_node(child.tree, rng) = *random_node(donor, rng);
    }
    if (rnd::uniform(rng, 0, 1) < kMutation) *random_node(child.tree, rng) = random_tree(t, rng, 3);
    if (node_total(child.tree) > (std::size_t{1} << max_depth)) continue;
    next.push_back(std::move(child));
  }
  return next;
}

// Non-dominated exact creatures (geometry 1): smaller size or higher proximity.
std::vector<ParetoPoint> pareto_front(const std::vector<Creature>& pop) {
  std::vector<ParetoPoint> front;
  for (const Creature& c : pop) {
    if (c.geometry < 1.0) continue;
    const bool dominated = std::any_of(pop.begin(), pop.end(), [&](const Creature& o) {
      return o.geometry >= 1.0 && o.size <= c.size && o.proximity >= c.proximity &&
             (o.size < c.size || o.proximity > c.proximity);
    });
    const bool repeated = std::any_of(front.begin(), front.end(), [&](const ParetoPoint& p) {
      return p.size == c.size && p.proximity == c.proximity;
    });
    if (!dominated && !repeated) front.push_back({c.tree, c.size, c.proximity});
  }
  std::sort(front.begin(), front.end(), [](auto& a, auto& b) { return a.size < b.size; });
  return front;
}

}  // namespace

template <std::size_t D>
Expr genetic_remaining(const Expr& solid, const SampleSet<D>& s, const OptimizeOptions& o,
                       std::vector<ParetoPoint>& front) {
  const auto start = std::chrono::steady_clock::now();
  const CitTable t = cit_table(solid, s);
  if (t.vars.size() < 2) return solid;
  rnd::Rng rng(rnd::splitmix(o.seed ^ 0x9a));
  const Expr input = binary(solid);
  std::size_t max_depth = 2;
  while ((std::size_t{1} << max_depth) < node_total(input)) ++max_depth;
  std::vector<Creature> pop;
  for (std::size_t i = 0; i < kPopulation; ++i)
    pop.push_back({i % 2 == 0 ? input : random_tree(t, rng, max_depth), 0, 0, 0, 0});
  score_population(pop, t, o);
  double best_score = -1;
  for (std::size_t it = 0, stall = 0; it < kIterations && stall < kStall; ++it) {
    pop = next_generation(pop, t, rng, max_depth + 1);
    score_population(pop, t, o);
    const double top = std::max_element(pop.begin(), pop.end(), [](auto& a, auto& b) { return a.score < b.score; })->score;
    stall = top > best_score ? 0 : stall + 1;
    best_score = std::max(best_score, top);
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > o.time_limit) break;
  }
  front = pareto_front(pop);
  if (front.empty()) return solid;
  const auto best = std::max_element(pop.begin(), pop.end(), [](const Creature& a, const Creature& b) {
    return (a.geometry >= 1.0) != (b.geometry >= 1.0) ? b.geometry >= 1.0 : a.score < b.score;
  });
  Expr tree = best->tree;
  remove_redundancy(tree, s);
  return same_solid(tree, solid, s) ? tree : solid;
}

template Expr genetic_remaining<2>(const Expr&, const SampleSet<2>&, const OptimizeOptions&, std::vector<ParetoPoint>&);
template Expr genetic_remaining<3>(const Expr&, const SampleSet<3>&, const OptimizeOptions&, std::vector<ParetoPoint>&);

}  // namespace csgfit::opt
