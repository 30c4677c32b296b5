#include "csgfit/optimise/structural_rules.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace csgfit::opt {
namespace {

bool is(const Expr& e, ExprOp op) { return e.op == op; }

// Beyond this many operands the rules that compare every pair (absorption, the differences'
// factoring) are skipped: a 10^6-wide union stays linear.
constexpr std::size_t kPairwiseOperands = 2000;

// Dedupes structurally equal operands, keeping the first of each (hashed: linear in width).
bool dedupe(std::vector<Expr>& kids, std::size_t from = 0) {
  const std::size_t before = kids.size();
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> seen;
  std::vector<Expr> out(kids.begin(), kids.begin() + static_cast<std::ptrdiff_t>(from));
  for (std::size_t i = from; i < kids.size(); ++i) {
    std::vector<std::size_t>& same_hash = seen[structural_hash(kids[i])];
    const bool repeated = std::any_of(same_hash.begin(), same_hash.end(), [&](std::size_t j) { return out[j] == kids[i]; });
    if (repeated) continue;
    same_hash.push_back(out.size());
    out.push_back(std::move(kids[i]));
  }
  kids = std::move(out);
  return kids.size() != before;
}

// Splices children with the same associative operator into their parent.
bool flatten(Expr& e) {
  bool changed = false;
  std::vector<Expr> out;
  for (Expr& k : e.kids) {
    if (k.op == e.op) {
      for (Expr& g : k.kids) out.push_back(std::move(g));
      changed = true;
    } else {
      out.push_back(std::move(k));
    }
  }
  e.kids = std::move(out);
  return changed;
}

// X | (X & A) = X and X & (X | A) = X: an operand made of another operand and more.
bool absorb(Expr& e, ExprOp inner) {
  bool changed = false;
  for (std::size_t i = 0; i < e.kids.size(); ++i) {
    for (std::size_t j = 0; j < e.kids.size(); ++j) {
      const Expr& big = e.kids[j];
      if (i == j || !is(big, inner)) continue;
      if (std::find(big.kids.begin(), big.kids.end(), e.kids[i]) == big.kids.end()) continue;
      e.kids.erase(e.kids.begin() + static_cast<std::ptrdiff_t>(j));
      changed = true;
      if (j < i) --i;
      j = static_cast<std::size_t>(-1);
    }
  }
  return changed;
}

// (X & A) | (X & B) = X & (A | B), and dually: the common operand that most siblings share is
// factored out. Returns false when no two siblings share one.
bool factor_common(Expr& e, ExprOp inner) {
  std::map<std::uint64_t, std::size_t> count;
  for (const Expr& k : e.kids) {
    if (!is(k, inner)) continue;
    std::vector<std::uint64_t> seen;
    for (const Expr& g : k.kids) seen.push_back(structural_hash(g));
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    for (std::uint64_t h : seen) ++count[h];
  }
  std::uint64_t best = 0;
  std::size_t best_count = 1;
  for (const auto& [h, c] : count) {
    if (c > best_count) best = h, best_count = c;
  }
  if (best_count < 2) return false;
  Expr common;
  std::vector<Expr> rests, others;
  for (Expr& k : e.kids) {
    auto at = is(k, inner) ? std::find_if(k.kids.begin(), k.kids.end(),
                                          [&](const Expr& g) { return structural_hash(g) == best; })
                           : k.kids.end();
    if (at == k.kids.end()) {
      others.push_back(std::move(k));
      continue;
    }
    common = std::move(*at);
    k.kids.erase(at);
    rests.push_back(k.kids.size() == 1 ? std::move(k.kids[0]) : std::move(k));
  }
  Expr factored = Expr::make(inner, {std::move(common), Expr::make(e.op, std::move(rests))});
  if (others.empty()) {
    e = std::move(factored);
  } else {
    others.push_back(std::move(factored));
    e.kids = std::move(others);
  }
  return true;
}

// (A - C) | (B - C) = (A | B) - C and (A - B) | (A - C) = A - (B & C), for two differences
// among a union's operands.
bool factor_differences(Expr& e) {
  for (std::size_t i = 0; i < e.kids.size(); ++i) {
    for (std::size_t j = i + 1; j < e.kids.size(); ++j) {
      Expr& a = e.kids[i];
      Expr& b = e.kids[j];
      if (!is(a, ExprOp::Difference) || !is(b, ExprOp::Difference)) continue;
      const bool same_cut = std::equal(a.kids.begin() + 1, a.kids.end(), b.kids.begin() + 1, b.kids.end());
      const bool same_base = a.kids[0] == b.kids[0];
      if (!same_cut && !same_base) continue;
      Expr merged;
      if (same_cut) {
        std::vector<Expr> kids(a.kids.begin() + 1, a.kids.end());
        kids.insert(kids.begin(), Expr::make(ExprOp::Union, {std::move(a.kids[0]), std::move(b.kids[0])}));
        merged = Expr::make(ExprOp::Difference, std::move(kids));
      } else {
        auto cut_of = [](Expr& d) {
          std::vector<Expr> cut(d.kids.begin() + 1, d.kids.end());
          return cut.size() == 1 ? std::move(cut[0]) : Expr::make(ExprOp::Union, std::move(cut));
        };
        Expr cut = Expr::make(ExprOp::Intersection, {cut_of(a), cut_of(b)});
        merged = Expr::make(ExprOp::Difference, {std::move(a.kids[0]), std::move(cut)});
      }
      e.kids[i] = std::move(merged);
      e.kids.erase(e.kids.begin() + static_cast<std::ptrdiff_t>(j));
      return true;
    }
  }
  return false;
}

std::size_t rewrite_complement(Expr& e) {
  Expr& k = e.kids[0];
  if (is(k, ExprOp::Complement)) {
    Expr inner = std::move(k.kids[0]);
    e = std::move(inner);
    return 1;
  }
  if (is(k, ExprOp::Empty) || is(k, ExprOp::Universe)) {
    e = is(k, ExprOp::Empty) ? Expr::universe() : Expr::empty();
    return 1;
  }
  return 0;
}

// Union and intersection alike, with `absorbing` the constant that swallows the operator and
// `neutral` the one that drops out.
std::size_t rewrite_associative(Expr& e, ExprOp absorbing, ExprOp neutral, ExprOp dual) {
  std::size_t n = flatten(e);
  if (std::any_of(e.kids.begin(), e.kids.end(), [&](const Expr& k) { return is(k, absorbing); })) {
    e = absorbing == ExprOp::Empty ? Expr::empty() : Expr::universe();
    return n + 1;
  }
  const std::size_t before = e.kids.size();
  e.kids.erase(std::remove_if(e.kids.begin(), e.kids.end(), [&](const Expr& k) { return is(k, neutral); }),
               e.kids.end());
  n += before != e.kids.size();
  n += dedupe(e.kids);
  const bool pairwise = e.kids.size() <= kPairwiseOperands;
  if (pairwise) n += absorb(e, dual);
  if (e.kids.size() > 1 && factor_common(e, dual)) ++n;
  if (pairwise && e.op == ExprOp::Union && e.kids.size() > 1 && factor_differences(e)) ++n;
  if (e.kids.empty()) {
    e = neutral == ExprOp::Empty ? Expr::empty() : Expr::universe();
    return n + 1;
  }
  if (e.is_operator() && e.kids.size() == 1) {
    Expr only = std::move(e.kids[0]);
    e = std::move(only);
    return n + 1;
  }
  return n;
}

// a - (a - c) = a & c (with more subtrahends on either side: a - (a - c - d) - f =
// (a & (c | d)) - f); what a double complement written with a bounding solid comes back as.
std::size_t cut_of_own_cut(Expr& e) {
  for (std::size_t i = 1; i < e.kids.size(); ++i) {
    Expr& k = e.kids[i];
    if (!is(k, ExprOp::Difference) || k.kids[0] != e.kids[0]) continue;
    std::vector<Expr> c(k.kids.begin() + 1, k.kids.end());
    Expr kept = c.size() == 1 ? std::move(c[0]) : Expr::make(ExprOp::Union, std::move(c));
    e.kids.erase(e.kids.begin() + static_cast<std::ptrdiff_t>(i));
    e.kids[0] = Expr::make(ExprOp::Intersection, {std::move(e.kids[0]), std::move(kept)});
    if (e.kids.size() == 1) {
      Expr only = std::move(e.kids[0]);
      e = std::move(only);
    }
    return 1;
  }
  return 0;
}

std::size_t rewrite_difference(Expr& e) {
  std::size_t n = 0;
  if (is(e.kids[0], ExprOp::Difference)) {  // (a - b) - c = a - b - c
    Expr first = std::move(e.kids[0]);
    e.kids.erase(e.kids.begin());
    e.kids.insert(e.kids.begin(), std::make_move_iterator(first.kids.begin()),
                  std::make_move_iterator(first.kids.end()));
    ++n;
  }
  std::vector<Expr> kids;
  kids.push_back(std::move(e.kids[0]));
  for (std::size_t i = 1; i < e.kids.size(); ++i) {
    Expr& k = e.kids[i];
    if (is(k, ExprOp::Union)) {  // a - (b | c) = a - b - c
      for (Expr& g : k.kids) kids.push_back(std::move(g));
      ++n;
    } else if (is(k, ExprOp::Empty)) {
      ++n;
    } else {
      kids.push_back(std::move(k));
    }
  }
  e.kids = std::move(kids);
  n += dedupe(e.kids, 1);
  if (cut_of_own_cut(e)) return n + 1;
  const Expr& base = e.kids[0];
  const bool vanishes = is(base, ExprOp::Empty) ||
                        std::any_of(e.kids.begin() + 1, e.kids.end(), [&](const Expr& k) {
                          return is(k, ExprOp::Universe) || k == base;
                        });
  if (vanishes) {
    e = Expr::empty();
    return n + 1;
  }
  if (e.kids.size() == 1) {
    Expr only = std::move(e.kids[0]);
    e = std::move(only);
    return n + 1;
  }
  if (is(e.kids[0], ExprOp::Universe)) {  // U - b - c = ~(b | c)
    std::vector<Expr> cut(e.kids.begin() + 1, e.kids.end());
    e = Expr::complement(cut.size() == 1 ? std::move(cut[0]) : Expr::make(ExprOp::Union, std::move(cut)));
    return n + 1;
  }
  return n;
}

std::size_t rewrite_once(Expr& e) {
  std::size_t n = 0;
  for (Expr& k : e.kids) n += rewrite_once(k);
  switch (e.op) {
    case ExprOp::Complement: return n + rewrite_complement(e);
    case ExprOp::Union:
      return n + rewrite_associative(e, ExprOp::Universe, ExprOp::Empty, ExprOp::Intersection);
    case ExprOp::Intersection:
      return n + rewrite_associative(e, ExprOp::Empty, ExprOp::Universe, ExprOp::Union);
    case ExprOp::Difference: return n + rewrite_difference(e);
    default: return n;
  }
}

}  // namespace

std::size_t apply_structural_rules(Expr& e) {
  std::size_t total = 0;
  for (int pass = 0; pass < 64; ++pass) {
    const std::size_t n = rewrite_once(e);
    total += n;
    if (n == 0) break;
  }
  return total;
}

}  // namespace csgfit::opt
