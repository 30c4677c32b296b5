#include "csgfit/optimise/expression.h"

#include <algorithm>

#include "csgfit/optimise/structural_rules.h"

namespace csgfit::opt {

std::size_t expression_size(const Expr& e) {
  if (e.op == ExprOp::Empty || e.op == ExprOp::Universe) return 0;
  std::size_t n = 1;
  for (const Expr& k : e.kids) n += expression_size(k);
  return n;
}

std::size_t literal_count(const Expr& e) {
  if (e.is_leaf()) return 1;
  std::size_t n = 0;
  for (const Expr& k : e.kids) n += literal_count(k);
  return n;
}

static void collect_halfspaces(const Expr& e, std::vector<int>& out) {
  if (e.op == ExprOp::Halfspace) out.push_back(e.index);
  for (const Expr& k : e.kids) collect_halfspaces(k, out);
}

std::vector<int> halfspaces_used(const Expr& e) {
  std::vector<int> out;
  collect_halfspaces(e, out);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool has_opaque(const Expr& e) {
  if (e.op == ExprOp::Opaque) return true;
  return std::any_of(e.kids.begin(), e.kids.end(), [](const Expr& k) { return has_opaque(k); });
}

std::uint64_t structural_hash(const Expr& e) {
  std::uint64_t h = 0x9e3779b97f4a7c15ULL * (static_cast<std::uint64_t>(e.op) + 1);
  h ^= static_cast<std::uint64_t>(e.index + 2) * 0xbf58476d1ce4e5b9ULL;
  for (const Expr& k : e.kids) {
    h = (h ^ structural_hash(k)) * 0x94d049bb133111ebULL;
    h ^= h >> 29;
  }
  return h;
}

void substitute(Expr& e, int index, const Expr& by) {
  if (e.op == ExprOp::Halfspace && e.index == index) {
    e = by;
    return;
  }
  for (Expr& k : e.kids) substitute(k, index, by);
}

static const char* op_name(ExprOp op) {
  switch (op) {
    case ExprOp::Halfspace: return "h";
    case ExprOp::Opaque: return "opaque";
    case ExprOp::Empty: return "empty";
    case ExprOp::Universe: return "universe";
    case ExprOp::Complement: return "not";
    case ExprOp::Union: return "union";
    case ExprOp::Intersection: return "inter";
    case ExprOp::Difference: return "diff";
  }
  return "?";
}

std::string to_text(const Expr& e) {
  if (e.op == ExprOp::Halfspace) return "h" + std::to_string(e.index);
  if (e.op == ExprOp::Opaque) return "opaque" + std::to_string(e.index);
  std::string s = op_name(e.op);
  if (!e.is_operator()) return s;
  s += '(';
  for (std::size_t i = 0; i < e.kids.size(); ++i) s += (i ? ", " : "") + to_text(e.kids[i]);
  return s + ')';
}

namespace {

// A node as a positive expression `set`, meaning `set` itself or, when `negated`, its
// complement.
struct Signed {
  Expr set;
  bool negated = false;
};

Signed signed_form(Expr e);

Expr op_or_single(ExprOp op, std::vector<Expr> kids) {
  if (kids.size() == 1) return std::move(kids[0]);
  return Expr::make(op, std::move(kids));
}

// The intersection of literals that are sets or complements: A & B & ~C = (A & B) - C.
Signed intersect_signed(std::vector<Signed> parts) {
  std::vector<Expr> pos, neg;
  for (Signed& s : parts) (s.negated ? neg : pos).push_back(std::move(s.set));
  if (pos.empty()) return {op_or_single(ExprOp::Union, std::move(neg)), true};
  Expr base = op_or_single(ExprOp::Intersection, std::move(pos));
  if (neg.empty()) return {std::move(base), false};
  neg.insert(neg.begin(), std::move(base));
  return {Expr::make(ExprOp::Difference, std::move(neg)), false};
}

// A | B | ~C = ~(C - (A | B)).
Signed unite_signed(std::vector<Signed> parts) {
  std::vector<Expr> pos, neg;
  for (Signed& s : parts) (s.negated ? neg : pos).push_back(std::move(s.set));
  if (neg.empty()) return {op_or_single(ExprOp::Union, std::move(pos)), false};
  Expr core = op_or_single(ExprOp::Intersection, std::move(neg));
  if (pos.empty()) return {std::move(core), true};
  return {Expr::make(ExprOp::Difference, {std::move(core), op_or_single(ExprOp::Union, std::move(pos))}),
          true};
}

Signed signed_form(Expr e) {
  switch (e.op) {
    case ExprOp::Universe: return {Expr::empty(), true};
    case ExprOp::Complement: {
      Signed s = signed_form(std::move(e.kids[0]));
      s.negated = !s.negated;
      return s;
    }
    case ExprOp::Union:
    case ExprOp::Intersection:
    case ExprOp::Difference: {
      std::vector<Signed> parts;
      for (std::size_t i = 0; i < e.kids.size(); ++i) {
        Signed s = signed_form(std::move(e.kids[i]));
        if (e.op == ExprOp::Difference && i > 0) s.negated = !s.negated;
        parts.push_back(std::move(s));
      }
      return e.op == ExprOp::Union ? unite_signed(std::move(parts)) : intersect_signed(std::move(parts));
    }
    default: return {std::move(e), false};
  }
}

}  // namespace

bool eliminate_complements(Expr& e) {
  Signed s = signed_form(std::move(e));
  e = std::move(s.set);
  apply_structural_rules(e);
  if (s.negated) e = Expr::complement(std::move(e));
  return !s.negated;
}

}  // namespace csgfit::opt
