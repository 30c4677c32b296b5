#include "cover.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <unordered_map>

#include "model/linalg.h"
#include "tuning.h"

namespace csgfit::construct {

namespace {

using namespace linalg;
using Clock = std::chrono::steady_clock;

bool bit(const Column& c, std::size_t i) { return (c[i / 64] >> (i % 64)) & 1; }

// The samples on the term's side of its halfspace.
Column side(const Cells& cells, const Term& t) {
  Column c = cells.columns[static_cast<std::size_t>(t.literal)];
  if (!t.inside)
    for (std::size_t w = 0; w < c.size(); ++w) c[w] = ~c[w] & cells.samples->real[w];
  return c;
}

// Weighted counts of a & b and of a & ~b (face samples weighed apart from voxels).
struct Weigher {
  const Samples& s;
  double count(std::uint64_t bits, std::size_t w) const {
    const double n = static_cast<double>(__builtin_popcountll(bits));
    return w < s.face_word ? n : s.face_weight * n;
  }
  double of(const Column& a) const {
    double sum = 0;
    for (std::size_t w = 0; w < a.size(); ++w) sum += count(a[w], w);
    return sum;
  }
  double both(const Column& a, const Column& b) const {
    double sum = 0;
    for (std::size_t w = 0; w < a.size(); ++w) sum += count(a[w] & b[w], w);
    return sum;
  }
  double first_only(const Column& a, const Column& b) const {
    double sum = 0;
    for (std::size_t w = 0; w < a.size(); ++w) sum += count(a[w] & ~b[w], w);
    return sum;
  }
};

void and_with(Column& a, const Column& b) {
  for (std::size_t w = 0; w < a.size(); ++w) a[w] &= b[w];
}
void or_with(Column& a, const Column& b) {
  for (std::size_t w = 0; w < a.size(); ++w) a[w] |= b[w];
}
void remove(Column& a, const Column& b) {
  for (std::size_t w = 0; w < a.size(); ++w) a[w] &= ~b[w];
}

// A candidate: a product and the holes it leaves to be cut (empty samples it holds).
struct Candidate {
  Product product;
  std::vector<int> excused;
  Column covered;  // samples inside the product
  double cost = 0;
  // The words of `covered` that have samples: a hole is a few words of the samples, and the
  // growths of positives ask every hole many times what it takes out.
  std::vector<std::pair<std::size_t, std::uint64_t>> words;
  void index_words() {
    words.clear();
    for (std::size_t w = 0; w < covered.size(); ++w)
      if (covered[w]) words.emplace_back(w, covered[w]);
  }
};

// What a growth may spend: the price of a literal (a fifth of a primitive for a plane: five of
// them make a box) and of leaving a hole to be cut, in weighted samples.
struct Prices {
  double literal = 0, hole = std::numeric_limits<double>::infinity();
};

// What each term (a literal, each side) takes out of the forbidden samples and loses of the
// target at a growth's first step, which is the same for every seed of one region: counted
// once, not once per seed (the first step counts the most words).
// off_side looks at its running count every this many + 1 words (a power of two less one).
constexpr std::size_t kCheckEvery = 15;

struct FirstCounts {
  std::vector<double> removed[2], lost[2];  // [inside][literal]
};

struct Growth {
  const Cells& cells;
  const Weigher& weigh;
  const Column& target;     // samples the product should keep (the class it grows in)
  const Column& forbidden;  // samples it must not hold (unless excused)
  const std::vector<Candidate>* holes = nullptr;
  Prices prices;
  const FirstCounts* first = nullptr;
  const std::vector<double>* price = nullptr;  // per literal, of a term of it to this growth
  std::size_t* words_counted = nullptr;  // the work done, against kMostWordsCounted
};

double literal_price(const Literal& l) { return l.plane ? (l.separating ? kSeparatingPlaneCost : kPlaneCost) : 1.0; }

// Weighted count, over the listed words, of `bits` off the term's side; the counting stops
// once it passes `enough` (the term has lost too much to win), returning what it has so far.
double off_side(const Cells& cells, const Term& t, const Column& bits, const std::vector<std::uint32_t>& words,
                double enough = std::numeric_limits<double>::infinity()) {
  const Column& col = cells.columns[static_cast<std::size_t>(t.literal)];
  const Column& real = cells.samples->real;
  const std::size_t face = cells.samples->face_word;
  const double fw = cells.samples->face_weight;
  std::size_t n[2] = {0, 0};
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::uint32_t w = words[i];
    const std::uint64_t off = t.inside ? ~col[w] : (col[w] & real[w]);
    n[w >= face] += static_cast<std::size_t>(__builtin_popcountll(bits[w] & off));
    if ((i & kCheckEvery) == kCheckEvery && static_cast<double>(n[0]) + fw * static_cast<double>(n[1]) > enough) break;
  }
  return static_cast<double>(n[0]) + fw * static_cast<double>(n[1]);
}

// The words of a column that have bits: the forbidden samples left after a few steps are a
// few scattered words, and each step counts them for every literal (on a CAD part with 600
// literals this loop was nine tenths of the construction).
std::vector<std::uint32_t> words_of(const Column& c) {
  std::vector<std::uint32_t> out;
  for (std::size_t w = 0; w < c.size(); ++w)
    if (c[w]) out.push_back(static_cast<std::uint32_t>(w));
  return out;
}

// One step: the term or hole that takes the most forbidden samples out for the least loss.
// What a term takes out only shrinks as the product grows, so `removed` holds, per literal,
// what it took out when last counted: terms are tried in the order of that bound and counted
// again only while the bound could still beat the best; what a term loses is counted only for
// terms whose recount could still win, and only until it cannot.
bool grow_step(const Growth& g, std::size_t seed, Candidate& c, Column& rest, std::vector<double>& removed) {
  const double eps = g.cells.samples->face_weight;
  double best = 0;
  int pick_literal = -1, pick_hole = -1;
  Column kept = c.covered;
  and_with(kept, g.target);
  const bool first = g.first && c.product.empty() && c.excused.empty();
  std::vector<std::uint32_t> rest_words, kept_words;
  if (!first) rest_words = words_of(rest), kept_words = words_of(kept);
  if (g.words_counted) *g.words_counted += rest_words.size() * g.cells.columns.size() + kept_words.size();
  const std::vector<double>& price = *g.price;
  std::vector<std::size_t> order(price.size());
  for (std::size_t l = 0; l < order.size(); ++l) order[l] = l;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return removed[a] / price[a] > removed[b] / price[b]; });
  for (const std::size_t l : order) {
    if (!(removed[l] / price[l] > best)) break;
    const Term t{static_cast<int>(l), bit(g.cells.columns[l], seed)};
    if (std::find(c.product.begin(), c.product.end(), t) != c.product.end()) continue;
    if (!first) removed[l] = off_side(g.cells, t, rest, rest_words);
    if (!(removed[l] / price[l] > best)) continue;
    // A term that loses more than this cannot beat the best: its count may stop there.
    const double enough = best > 0 ? removed[l] / best - price[l] : std::numeric_limits<double>::infinity();
    const double lost = first ? g.first->lost[t.inside][l] : off_side(g.cells, t, kept, kept_words, enough);
    const double score = removed[l] / (lost + price[l]);
    if (score > best) best = score, pick_literal = static_cast<int>(l), pick_hole = -1;
  }
  if (g.holes && std::isfinite(g.prices.hole))
    for (std::size_t h = 0; h < g.holes->size(); ++h) {
      if (std::find(c.excused.begin(), c.excused.end(), static_cast<int>(h)) != c.excused.end()) continue;
      double excused = 0;
      for (const auto& [w, bits] : (*g.holes)[h].words) excused += g.weigh.count(rest[w] & bits, w);
      const double score = excused / ((*g.holes)[h].cost * g.prices.hole + eps);
      if (excused > 0 && score > best) best = score, pick_literal = -1, pick_hole = static_cast<int>(h);
    }
  if (pick_literal >= 0) {
    const Term t{pick_literal, bit(g.cells.columns[static_cast<std::size_t>(pick_literal)], seed)};
    c.product.push_back(t);
    const Column s = side(g.cells, t);
    and_with(c.covered, s);
    and_with(rest, s);
    return true;
  }
  if (pick_hole >= 0) {
    c.excused.push_back(pick_hole);
    for (const auto& [w, bits] : (*g.holes)[static_cast<std::size_t>(pick_hole)].words) rest[w] &= ~bits;
    return true;
  }
  return false;
}

// Forbidden samples the candidate holds that none of its holes takes away.
Column left_over(const Growth& g, const Candidate& c) {
  Column rest = g.forbidden;
  and_with(rest, c.covered);
  for (int h : c.excused)
    for (const auto& [w, bits] : (*g.holes)[static_cast<std::size_t>(h)].words) rest[w] &= ~bits;
  return rest;
}

// Drops terms and holes the candidate does not need (the product grows: Espresso's EXPAND).
void expand(const Growth& g, Candidate& c) {
  for (std::size_t k = c.product.size(); k-- > 0;) {
    Candidate trial = c;
    trial.product.erase(trial.product.begin() + static_cast<long>(k));
    trial.covered = coverage(trial.product, g.cells);
    if (g.weigh.of(left_over(g, trial)) <= g.weigh.of(left_over(g, c))) c = std::move(trial);
  }
  for (std::size_t k = c.excused.size(); k-- > 0;) {
    Candidate trial = c;
    trial.excused.erase(trial.excused.begin() + static_cast<long>(k));
    if (g.weigh.of(left_over(g, trial)) <= g.weigh.of(left_over(g, c))) c = std::move(trial);
  }
}

// The cheapest holes (greedily) that take every sample of `rest` away; false if none can.
bool holes_for(const std::vector<Candidate>& holes, Column rest, const Weigher& weigh,
               std::vector<int>& chosen, double& cost) {
  cost = 0;
  while (weigh.of(rest) > 0) {
    double best = 0;
    int pick = -1;
    for (std::size_t h = 0; h < holes.size(); ++h) {
      double taken = 0;
      for (const auto& [w, bits] : holes[h].words) taken += weigh.count(rest[w] & bits, w);
      if (taken / holes[h].cost > best) best = taken / holes[h].cost, pick = static_cast<int>(h);
    }
    if (pick < 0) return false;
    chosen.push_back(pick);
    cost += holes[static_cast<std::size_t>(pick)].cost;
    for (const auto& [w, bits] : holes[static_cast<std::size_t>(pick)].words) rest[w] &= ~bits;
  }
  return true;
}

FirstCounts first_counts(const Growth& g, const Column& region) {
  Column rest = g.forbidden, kept = region;
  and_with(rest, region);
  and_with(kept, g.target);
  const std::vector<std::uint32_t> rest_words = words_of(rest), kept_words = words_of(kept);
  FirstCounts out;
  for (int inside = 0; inside < 2; ++inside)
    for (std::size_t l = 0; l < g.cells.columns.size(); ++l) {
      const Term t{static_cast<int>(l), inside == 1};
      out.removed[inside].push_back(off_side(g.cells, t, rest, rest_words));
      out.lost[inside].push_back(off_side(g.cells, t, kept, kept_words));
    }
  return out;
}

// The largest product about the seed that holds no forbidden sample (but what its holes take
// away); nullopt-like empty product with `ok` false when some cannot be separated.
bool grow(const Growth& g, std::size_t seed, const Column& region, Candidate& out, int start = -1) {
  Candidate c;
  c.covered = region;
  Column rest = g.forbidden;
  and_with(rest, region);
  if (start >= 0) {
    const Term t{start, true};
    c.product.push_back(t);
    const Column s = side(g.cells, t);
    and_with(c.covered, s);
    and_with(rest, s);
  }
  // What each term takes out at the first step (the most it ever takes out).
  std::vector<double> removed(g.cells.columns.size(), std::numeric_limits<double>::infinity());
  if (g.first)
    for (std::size_t l = 0; l < removed.size(); ++l) removed[l] = g.first->removed[bit(g.cells.columns[l], seed)][l];
  for (int step = 0; step < kMostTerms && g.weigh.of(rest) > 0; ++step)
    if (!grow_step(g, seed, c, rest, removed)) break;
  expand(g, c);
  const double wrong = g.weigh.of(left_over(g, c));
  Column kept = c.covered;
  and_with(kept, g.target);
  if (wrong > kUnseparatedShare * g.weigh.of(kept)) return false;
  out = std::move(c);
  return true;
}

// Cells: samples with one signature over the literals; their representatives, largest first.
std::vector<std::size_t> seeds_in(const Cells& cells, const Column& among) {
  const Samples& s = *cells.samples;
  std::unordered_map<std::uint64_t, std::pair<std::size_t, double>> cell;  // hash -> (sample, weight)
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    if (!bit(among, i)) continue;
    std::uint64_t h = 1469598103934665603ULL;
    for (const Column& c : cells.columns) h = (h ^ (bit(c, i) ? 0x9e3779b97f4a7c15ULL : 0x2545f4914f6cdd1dULL)) * 1099511628211ULL;
    auto [it, fresh] = cell.try_emplace(h, i, 0.0);
    it->second.second += i / 64 < s.face_word ? 1.0 : s.face_weight;
  }
  std::vector<std::pair<double, std::size_t>> order;
  for (const auto& entry : cell) order.push_back({-entry.second.second, entry.second.first});
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> out;
  for (const auto& o : order) out.push_back(o.second);
  return out;
}

bool has_product(const std::vector<Candidate>& list, const Product& p) {
  const auto sorted = [](Product q) {
    std::sort(q.begin(), q.end(), [](const Term& a, const Term& b) { return std::tie(a.literal, a.inside) < std::tie(b.literal, b.inside); });
    return q;
  };
  const Product key = sorted(p);
  return std::any_of(list.begin(), list.end(), [&](const Candidate& c) { return sorted(c.product) == key; });
}

// Candidates grown from every cell of `among` not yet inside one grown before, and from each
// primitive.
void grow_all(const Growth& g, const Column& among, const Column& region, Clock::time_point deadline,
              std::vector<Candidate>& out) {
  Column taken(among.size(), 0);
  std::size_t attempts = 0;
  const FirstCounts first = first_counts(g, region);
  std::vector<double> price;
  for (const Literal& l : *g.cells.literals) price.push_back(literal_price(l) * g.prices.literal + g.cells.samples->face_weight);
  Growth counted = g;
  counted.first = &first;
  counted.price = &price;
  std::size_t words = 0;
  counted.words_counted = &words;
  const std::vector<std::size_t> seeds = seeds_in(g.cells, among);
  const auto spent = [&] {
    return Clock::now() > deadline || out.size() >= kMostCandidates || ++attempts > kMostGrowths || words > kMostWordsCounted;
  };
  const auto keep = [&](Candidate& c) {
    c.cost = product_cost(c.product, *g.cells.literals);
    or_with(taken, c.covered);
    c.index_words();
    out.push_back(std::move(c));
  };
  for (std::size_t seed : seeds) {
    if (bit(taken, seed)) continue;
    if (spent()) break;
    Candidate c;
    if (!grow(counted, seed, region, c)) {
      taken[seed / 64] |= 1ULL << (seed % 64);
      continue;
    }
    keep(c);
  }
  // The greedy growth from a cell is myopic: a primitive that holds cells on both sides of a
  // step (a plate's outline running on under a smaller one) loses to the planes that split
  // them. So each primitive also starts a growth of its own, from its largest cell.
  for (std::size_t l = 0; l < g.cells.literals->size(); ++l) {
    if ((*g.cells.literals)[l].plane) continue;
    const auto seed = std::find_if(seeds.begin(), seeds.end(), [&](std::size_t i) { return bit(g.cells.columns[l], i); });
    if (seed == seeds.end()) continue;
    if (spent()) break;
    Candidate c;
    if (grow(counted, *seed, region, c, static_cast<int>(l)) && !has_product(out, c.product)) keep(c);
  }
}

// Seed 001's dominant halfspaces: the sides that hold every solid sample and cut off some empty.
Product envelope_of(const Cells& cells, const Weigher& weigh, const Column& solid, const Column& empty) {
  Product e;
  for (std::size_t l = 0; l < cells.columns.size(); ++l)
    for (bool inside : {true, false}) {
      const Column s = side(cells, {static_cast<int>(l), inside});
      if (weigh.first_only(solid, s) == 0 && weigh.first_only(empty, s) > 0) e.push_back({static_cast<int>(l), inside});
    }
  // Only the sides that cut off something the others keep: the faces of a chamfer made of many
  // facets each hold the solid, and one of them, or the box, says it all. Curved and turned
  // sides go first, the model axes' planes (one box) last.
  const auto rank = [&](const Term& t) {
    const Literal& l = (*cells.literals)[static_cast<std::size_t>(t.literal)];
    return !l.plane ? 0 : (model_axis(l.normal) < 0 ? 1 : 2);
  };
  std::stable_sort(e.begin(), e.end(), [&](const Term& a, const Term& b) { return rank(a) < rank(b); });
  const double outside = weigh.first_only(empty, coverage(e, cells));
  for (std::size_t k = 0; k < e.size();) {
    Product without = e;
    without.erase(without.begin() + static_cast<long>(k));
    if (weigh.first_only(empty, coverage(without, cells)) >= outside) e = std::move(without);
    else ++k;
  }
  return e;
}

// Greedy weighted set cover: positives by solid samples newly covered per primitive, a
// positive's price including the holes it needs that are not cut yet; `first`, when not -1, is
// taken before the greedy starts.
void choose(const std::vector<Candidate>& positives, const std::vector<Candidate>& holes,
              const Column& solid, const Weigher& weigh, int first, Cover& cover) {
  Column covered(solid.size(), 0);
  std::vector<char> hole_chosen(holes.size(), 0), chosen(positives.size(), 0);
  for (int pick = first;; pick = -1) {
    double best = 0;
    for (std::size_t k = 0; pick < 0 && k < positives.size(); ++k) {
      if (chosen[k]) continue;
      Column fresh = positives[k].covered;
      and_with(fresh, solid);
      remove(fresh, covered);
      double cost = positives[k].cost;
      for (int h : positives[k].excused) cost += hole_chosen[static_cast<std::size_t>(h)] ? 0 : holes[static_cast<std::size_t>(h)].cost;
      const double ratio = weigh.of(fresh) / std::max(cost, 0.5);
      if (ratio > best) best = ratio, first = static_cast<int>(k);
    }
    if (pick < 0 && !(best > 0)) break;
    if (pick < 0) pick = first;
    chosen[static_cast<std::size_t>(pick)] = 1;
    const Candidate& c = positives[static_cast<std::size_t>(pick)];
    Column in = c.covered;
    and_with(in, solid);
    or_with(covered, in);
    for (int h : c.excused) hole_chosen[static_cast<std::size_t>(h)] = 1;
    cover.positives.push_back(c.product);
  }
  for (std::size_t h = 0; h < holes.size(); ++h)
    if (hole_chosen[h]) cover.holes.push_back(holes[h].product);
}

// Drops the positives the others cover, latest first, then the holes no positive needs.
void drop_redundant(const Cells& cells, const Column& solid, const Column& empty, const Weigher& weigh, Cover& cover) {
  std::vector<Column> pos, hole;
  for (const Product& p : cover.positives) pos.push_back(coverage(p, cells));
  for (const Product& h : cover.holes) hole.push_back(coverage(h, cells));
  const auto union_of = [&](const std::vector<Column>& cols, std::size_t skip) {
    Column u(solid.size(), 0);
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (k != skip) or_with(u, cols[k]);
    return u;
  };
  for (std::size_t k = pos.size(); k-- > 0;) {
    if (weigh.first_only(solid, union_of(pos, k)) > weigh.first_only(solid, union_of(pos, pos.size()))) continue;
    pos.erase(pos.begin() + static_cast<long>(k));
    cover.positives.erase(cover.positives.begin() + static_cast<long>(k));
  }
  Column inside = union_of(pos, pos.size());
  and_with(inside, empty);
  for (std::size_t k = hole.size(); k-- > 0;) {
    Column left = inside, with = inside;
    remove(left, union_of(hole, k));
    remove(with, union_of(hole, hole.size()));
    if (weigh.of(left) > weigh.of(with)) continue;
    hole.erase(hole.begin() + static_cast<long>(k));
    cover.holes.erase(cover.holes.begin() + static_cast<long>(k));
  }
}

}  // namespace

Cells cells_of(const Samples& samples, const std::vector<Literal>& literals) {
  Cells c;
  c.samples = &samples;
  c.literals = &literals;
  for (const Literal& l : literals) {
    Column col = literal_column(l, samples);
    and_with(col, samples.real);
    c.columns.push_back(std::move(col));
  }
  return c;
}

Column coverage(const Product& p, const Cells& cells) {
  Column c = cells.samples->real;
  for (const Term& t : p) and_with(c, side(cells, t));
  return c;
}

double product_cost(const Product& p, const std::vector<Literal>& literals) {
  double cost = 0;
  bool model_box = false;
  std::vector<Vec3> other_frames, curved_axes;
  for (const Term& t : p) {
    const Literal& l = literals[static_cast<std::size_t>(t.literal)];
    if (!l.plane) {
      cost += 1;
      if (t.inside && l.solid.kind != PrimitiveKind3D::Sphere) curved_axes.push_back(column(l.solid.rotation.matrix(), 2));
    }
  }
  for (const Term& t : p) {
    const Literal& l = literals[static_cast<std::size_t>(t.literal)];
    if (!l.plane) continue;
    // A cap across a cylinder's axis is the cylinder's own end.
    if (std::any_of(curved_axes.begin(), curved_axes.end(), [&](const Vec3& a) { return norm(cross(a, l.normal)) < 1e-9; })) continue;
    if (model_axis(l.normal) >= 0) {
      model_box = true;
    } else if (std::none_of(other_frames.begin(), other_frames.end(), [&](const Vec3& n) { return norm(cross(n, l.normal)) < 1e-9; })) {
      other_frames.push_back(l.normal);
    }
  }
  return cost + (model_box ? 1 : 0) + static_cast<double>(other_frames.size());
}

Cover cover_cells(const Cells& cells, Clock::time_point deadline) {
  const Samples& s = *cells.samples;
  const Weigher weigh{s};
  Column solid = s.inside, empty = s.real;
  and_with(solid, s.real);
  remove(empty, s.inside);
  Cover cover;
  cover.solid_weight = weigh.of(solid);
  cover.envelope = envelope_of(cells, weigh, solid, empty);
  const Column region = coverage(cover.envelope, cells);
  Column inner_empty = empty;
  and_with(inner_empty, region);
  // Holes: the largest products of empty samples inside the envelope, reaching out of it freely.
  std::vector<Candidate> holes, positives;
  const Growth hole_growth{cells, weigh, inner_empty, solid, nullptr, {kLiteralPrice * cover.solid_weight, std::numeric_limits<double>::infinity()}};
  grow_all(hole_growth, inner_empty, s.real, deadline, holes);
  // A hole a designer cut (a bore, a slot, a pocket) lies mostly between solid along some axis;
  // an empty region beside the part (the notch of an L, the room around a boss) does not. The
  // positives may fill the cut holes, which are then cut from them: the block before drilling.
  const Column enclosed = enclosed_empty(s);
  Column cut(s.words(), 0);
  for (const Candidate& h : holes) {
    Column in = h.covered;
    and_with(in, inner_empty);
    if (weigh.both(in, enclosed) >= kEnclosedShare * weigh.of(in)) or_with(cut, in);
  }
  Column beside = inner_empty;
  remove(beside, cut);
  const Growth g{cells, weigh, solid, beside, &holes, {kLiteralPrice * cover.solid_weight, std::numeric_limits<double>::infinity()}};
  grow_all(g, solid, region, deadline, positives);
  // And positives clear of every empty sample, for parts a hole's block would not simplify.
  const Growth strict{cells, weigh, solid, inner_empty, &holes, {kLiteralPrice * cover.solid_weight, std::numeric_limits<double>::infinity()}};
  grow_all(strict, solid, region, deadline, positives);
  // Each positive pays for the holes that cut away the empty samples it holds.
  std::vector<Candidate> paid;
  for (Candidate& c : positives) {
    Column inside_empty = c.covered;
    and_with(inside_empty, inner_empty);
    double cost = 0;
    if (holes_for(holes, inside_empty, weigh, c.excused, cost)) paid.push_back(std::move(c));
  }
  positives = std::move(paid);
  // The greedy cover is myopic: a small piece clear of every hole beats the block the holes
  // are cut from until the holes are paid for. So it also starts from each of the largest
  // candidates in turn, and the cheapest cover wins.
  std::vector<std::pair<double, int>> largest;
  for (std::size_t k = 0; k < positives.size(); ++k) largest.push_back({-weigh.both(positives[k].covered, solid), static_cast<int>(k)});
  std::sort(largest.begin(), largest.end());
  largest.resize(std::min(largest.size(), kCoverStarts));
  largest.insert(largest.begin(), {0, -1});
  double cheapest = std::numeric_limits<double>::infinity();
  const Product envelope = cover.envelope;
  for (const auto& start : largest) {
    Cover trial;
    trial.envelope = envelope;
    choose(positives, holes, solid, weigh, start.second, trial);
    drop_redundant(cells, solid, inner_empty, weigh, trial);
    double spent = 0;
    for (const auto* list : {&trial.positives, &trial.holes})
      for (const Product& p : *list) spent += product_cost(p, *cells.literals);
    if (spent < cheapest) cheapest = spent, cover.positives = trial.positives, cover.holes = trial.holes;
    if (Clock::now() > deadline) break;
  }
  // What the cover gets wrong.
  Column in_positive(s.words(), 0), in_hole(s.words(), 0);
  for (const Product& p : cover.positives) or_with(in_positive, coverage(p, cells));
  for (const Product& h : cover.holes) or_with(in_hole, coverage(h, cells));
  // Solid samples no positive holds or a hole takes away; empty ones a positive holds and no
  // hole takes away.
  Column kept = in_positive;
  remove(kept, in_hole);
  cover.missed = weigh.first_only(solid, kept);
  cover.extra = weigh.both(inner_empty, kept);
  return cover;
}

}  // namespace csgfit::construct
