// Two-level logic minimisation of the seed's "remaining solid" (seed 001, Sec. 5.3.1): the solid
// is a sampled truth table over its halfspaces, and a cover (a union of products of halfspace
// literals, the DCF) is sought with as few products as possible.
#pragma once

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

namespace csgfit::two_level {

/// n bits, packed 64 per word (bit i of the minterm = halfspace i).
using BitRow = std::vector<std::uint64_t>;

/// A sampled truth table: minterms of the solid (on) and of its outside (off); every other
/// minterm is a don't-care. Duplicates allowed on input (dedupe internally). An on-minterm that
/// is also off is an error (std::invalid_argument), as is a row of the wrong width.
struct TruthTable {
  std::size_t variables = 0;
  std::vector<BitRow> on, off;
};

/// A product of literals: variable i appears iff care bit i; positive iff value bit i.
/// Value bits outside care are zero (every function here keeps them so).
struct Cube {
  BitRow care, value;
  std::size_t literal_count() const;
  bool contains(const BitRow& minterm) const;
  bool operator==(const Cube&) const;
};
using Cover = std::vector<Cube>;

/// The table validated, its on- and off-set sorted and deduplicated: the on-set whose indices
/// SetCoverInstance refers to.
TruthTable deduplicated(const TruthTable&);

/// Every on-minterm is in some cube, no off-minterm in any: the contract of all minimisers.
bool covers_exactly(const TruthTable&, const Cover&);

/// Quine-McCluskey with Petrick-free exact cover (via set_cover_exact) over on + don't-cares;
/// don't-cares are enumerated, so refuses (throws std::length_error naming the limit) above
/// `max_variables` (default 16).
Cover quine_mccluskey(const TruthTable&, std::size_t max_variables = 16);

/// Espresso-style heuristic (EXPAND against the explicit off-set, IRREDUNDANT, REDUCE, repeat
/// until the cost (cubes, then literals) stops falling). Works for hundreds of variables and
/// thousands of minterms since the off-set is explicit. Deterministic.
Cover espresso(const TruthTable&);

/// The seed's prime implicants "by the definition": from each on-minterm, drop literals one at
/// a time while the cube stays clear of the off-set (several orders, deduplicated).
std::vector<Cube> prime_implicants(const TruthTable&);

/// A set cover instance: universe = on-minterm indices, subsets = cubes.
struct SetCoverInstance {
  std::size_t universe = 0;
  std::vector<std::vector<std::size_t>> subsets;
};

/// Which on-minterms (indices into `on`, e.g. deduplicated(table).on) each cube covers.
SetCoverInstance cover_instance(const std::vector<BitRow>& on, const std::vector<Cube>& cubes);

/// Exact minimum set cover by branch and bound (returns chosen subset indices); gives up after
/// `node_limit` nodes and returns the best found (greedy as the incumbent), `proven_optimal`
/// says which. Throws std::invalid_argument if some element is in no subset.
struct SetCoverResult {
  std::vector<std::size_t> chosen;
  bool proven_optimal = false;
};
SetCoverResult set_cover_exact(const SetCoverInstance&, std::size_t node_limit = 100000);

/// A QUBO: minimise offset + sum of weight * x_i * x_j over `terms` (i == j: a linear term).
/// Variables 0..subsets-1 are the x_alpha; then per element a its one-hot counts x_{a,1..M_a}.
struct Qubo {
  std::size_t n = 0;
  std::vector<std::tuple<std::size_t, std::size_t, double>> terms;
  double offset = 0.0;
  double energy(const std::vector<std::uint8_t>& x) const;
};

/// The seed's Eq. 3 (Lucas 2014, set cover): H = A sum_a (1 - sum_m x_{a,m})^2
/// + A sum_a (sum_m m x_{a,m} - sum_{alpha ∋ a} x_alpha)^2 + B sum_alpha x_alpha.
Qubo set_cover_qubo_matrix(const SetCoverInstance&, double A, double B);

/// The QUBO assignment of a choice of subsets: its x_alpha, and each element's count one-hot.
std::vector<std::uint8_t> qubo_assignment(const SetCoverInstance&,
                                          const std::vector<std::size_t>& chosen);

/// The seed's QUBO (Eq. 3, penalty A > B = 1) minimised by simulated annealing (the annealer in
/// place of D-Wave); seeded, deterministic; the result is repaired to a valid cover (add
/// greedy, drop redundant) if the annealer ends infeasible. Never proven optimal.
SetCoverResult set_cover_qubo(const SetCoverInstance&, std::uint64_t seed,
                              std::size_t sweeps = 2000);

/// Prime implicants + set cover: `exact` picks branch and bound, else the QUBO annealer.
Cover set_cover_minimise(const TruthTable&, bool exact, std::uint64_t seed);

}  // namespace csgfit::two_level
