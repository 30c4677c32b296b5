// The two-level minimisers of the seed's remaining solid (seed 001, Sec. 5.3.1): every cover
// exact, Quine-McCluskey and the exact set cover minimal against brute force, espresso near it.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "csgfit/optimise/two_level.h"

namespace tl = csgfit::two_level;

namespace {

// Each of the 2^n minterms on, off or (with probability dont_care) unsampled.
tl::TruthTable random_table(std::size_t n, std::uint64_t seed, double dont_care) {
  std::mt19937_64 rng(seed);
  tl::TruthTable t{n, {}, {}};
  for (std::uint64_t m = 0; m < (std::uint64_t{1} << n); ++m) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    if (u < dont_care) continue;
    (rng() & 1 ? t.on : t.off).push_back(tl::BitRow{m});
  }
  return t;
}

// Whether `k` of `masks` cover `full`, branching on the lowest uncovered element.
bool covers_in(const std::vector<std::uint64_t>& masks, std::uint64_t got, std::uint64_t full,
               std::size_t k) {
  if (got == full) return true;
  if (k == 0) return false;
  const std::uint64_t lowest = ~got & full & (~(~got & full) + 1);
  for (std::uint64_t mask : masks)
    if ((mask & lowest) && covers_in(masks, got | mask, full, k - 1)) return true;
  return false;
}

std::size_t minimum_cover(const std::vector<std::uint64_t>& masks, std::uint64_t full) {
  std::size_t k = 0;
  while (!covers_in(masks, 0, full, k)) ++k;
  return k;
}

// The fewest cubes of any exact cover, by enumerating all 3^n cubes (n <= 5).
std::size_t brute_force_minimum(const tl::TruthTable& t) {
  const std::size_t n = t.variables;
  std::vector<std::uint64_t> masks;
  for (std::uint64_t care = 0; care < (std::uint64_t{1} << n); ++care)
    for (std::uint64_t value = care;; value = (value - 1) & care) {
      const tl::Cube cube{{care}, {value}};
      bool clear = true;
      for (const auto& m : t.off) clear = clear && !cube.contains(m);
      std::uint64_t mask = 0;
      for (std::size_t k = 0; k < t.on.size(); ++k)
        if (cube.contains(t.on[k])) mask |= std::uint64_t{1} << k;
      if (clear && mask) masks.push_back(mask);
      if (value == 0) break;
    }
  const std::uint64_t full = t.on.size() == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << t.on.size()) - 1;
  return minimum_cover(masks, full);
}

tl::SetCoverInstance random_instance(std::mt19937_64& rng, std::size_t universe, std::size_t subsets) {
  tl::SetCoverInstance instance{universe, std::vector<std::vector<std::size_t>>(subsets)};
  for (std::size_t e = 0; e < universe; ++e) {
    instance.subsets[rng() % subsets].push_back(e);  // every element coverable
    for (auto& s : instance.subsets)
      if (rng() % 4 == 0 && (s.empty() || s.back() != e)) s.push_back(e);
  }
  return instance;
}

std::vector<std::uint64_t> masks_of(const tl::SetCoverInstance& instance) {
  std::vector<std::uint64_t> masks;
  for (const auto& s : instance.subsets) {
    std::uint64_t mask = 0;
    for (std::size_t e : s) mask |= std::uint64_t{1} << e;
    masks.push_back(mask);
  }
  return masks;
}

}  // namespace

TEST(TwoLevel, RandomTablesEveryMethodExactAndQmcMinimal) {
  double qmc_cubes = 0, espresso_cubes = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) {
    const std::size_t n = 3 + seed % 5;  // n = 8 costs the exact cover seconds a table
    const tl::TruthTable t = tl::deduplicated(random_table(n, seed, seed % 2 ? 0.5 : 0.0));
    const tl::Cover qmc = tl::quine_mccluskey(t);
    const tl::Cover esp = tl::espresso(t);
    ASSERT_TRUE(tl::covers_exactly(t, qmc)) << "seed " << seed;
    ASSERT_TRUE(tl::covers_exactly(t, esp)) << "seed " << seed;
    ASSERT_TRUE(tl::covers_exactly(t, tl::set_cover_minimise(t, true, seed))) << "seed " << seed;
    if (n <= 4) {  // the brute force is exponential in the cover size
      ASSERT_TRUE(tl::covers_exactly(t, tl::set_cover_minimise(t, false, seed))) << "seed " << seed;
      ASSERT_EQ(qmc.size(), brute_force_minimum(t)) << "seed " << seed;
    }
    qmc_cubes += static_cast<double>(qmc.size());
    espresso_cubes += static_cast<double>(esp.size());
  }
  std::printf("mean cubes: qmc %.3f, espresso %.3f\n", qmc_cubes / 200, espresso_cubes / 200);
  EXPECT_LE(espresso_cubes, 1.15 * qmc_cubes);
}

TEST(TwoLevel, SetCoverExactMatchesBruteForce) {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 100; ++round) {
    const auto instance = random_instance(rng, 1 + rng() % 14, 1 + rng() % 12);
    const auto result = tl::set_cover_exact(instance);
    EXPECT_TRUE(result.proven_optimal);
    const std::uint64_t full = (std::uint64_t{1} << instance.universe) - 1;
    EXPECT_EQ(result.chosen.size(), minimum_cover(masks_of(instance), full)) << "round " << round;
    std::uint64_t got = 0;
    for (std::size_t s : result.chosen) got |= masks_of(instance)[s];
    EXPECT_EQ(got, full);
  }
}

TEST(TwoLevel, QuboEnergyOfACoverIsItsSize) {
  std::mt19937_64 rng(11);
  for (int round = 0; round < 50; ++round) {
    const auto instance = random_instance(rng, 1 + rng() % 10, 1 + rng() % 8);
    const tl::Qubo q = tl::set_cover_qubo_matrix(instance, 2.0, 1.0);
    std::vector<std::size_t> all(instance.subsets.size());
    for (std::size_t s = 0; s < all.size(); ++s) all[s] = s;
    const auto cover = tl::set_cover_exact(instance).chosen;
    for (const auto& chosen : {all, cover}) {
      const auto x = tl::qubo_assignment(instance, chosen);
      ASSERT_EQ(x.size(), q.n);
      EXPECT_NEAR(q.energy(x), static_cast<double>(chosen.size()), 1e-9);
    }
    auto uncovered = cover;
    uncovered.pop_back();  // a minimum cover minus one subset leaves an element bare
    EXPECT_GT(q.energy(tl::qubo_assignment(instance, uncovered)), static_cast<double>(cover.size()));
    auto inconsistent = tl::qubo_assignment(instance, cover);
    inconsistent[0] ^= 1;  // x_0 flipped, counts left as they were
    EXPECT_GT(q.energy(inconsistent), static_cast<double>(cover.size()) - 1.0 + 1e-9);
  }
}

TEST(TwoLevel, AnnealerValidAndMostlyOptimal) {
  std::mt19937_64 rng(13);
  int optimal = 0, rounds = 60;
  for (int round = 0; round < rounds; ++round) {
    const auto instance = random_instance(rng, 4 + rng() % 12, 3 + rng() % 10);
    const auto annealed = tl::set_cover_qubo(instance, static_cast<std::uint64_t>(round), 500);
    std::uint64_t got = 0;
    for (std::size_t s : annealed.chosen) got |= masks_of(instance)[s];
    ASSERT_EQ(got, (std::uint64_t{1} << instance.universe) - 1) << "round " << round;
    optimal += annealed.chosen.size() == tl::set_cover_exact(instance).chosen.size() ? 1 : 0;
  }
  std::printf("annealer optimal in %d of %d\n", optimal, rounds);
  EXPECT_GE(optimal, rounds * 8 / 10);
}

TEST(TwoLevel, AnnealerIsDeterministic) {
  std::mt19937_64 rng(17);
  const auto instance = random_instance(rng, 12, 9);
  EXPECT_EQ(tl::set_cover_qubo(instance, 5).chosen, tl::set_cover_qubo(instance, 5).chosen);
}

// Seed 001's Fig. 3 kind of solid: h0 and (h1 or h2), every region sampled.
TEST(TwoLevel, HandCaseKnownPrimes) {
  tl::TruthTable t{3, {}, {}};
  for (std::uint64_t m = 0; m < 8; ++m) ((m & 1) && (m & 6) ? t.on : t.off).push_back({m});
  const std::vector<tl::Cube> primes = tl::prime_implicants(t);
  const tl::Cube h0h1{{0b011}, {0b011}}, h0h2{{0b101}, {0b101}};
  ASSERT_EQ(primes.size(), 2u);
  EXPECT_TRUE((primes[0] == h0h1 && primes[1] == h0h2) || (primes[0] == h0h2 && primes[1] == h0h1));
  const auto instance = tl::cover_instance(tl::deduplicated(t).on, primes);
  EXPECT_EQ(instance.universe, 3u);
  for (const tl::Cover& cover : {tl::quine_mccluskey(t), tl::espresso(t),
                                 tl::set_cover_minimise(t, true, 1), tl::set_cover_minimise(t, false, 1)}) {
    EXPECT_EQ(cover.size(), 2u);
    EXPECT_TRUE(tl::covers_exactly(t, cover));
  }
}

TEST(TwoLevel, WideEspresso) {
  const std::size_t n = 100;
  std::mt19937_64 rng(23);
  // The solid: a 3-term DNF of 3 literals each; samples random until 2000 on and 2000 off.
  std::vector<tl::Cube> terms(3, tl::Cube{tl::BitRow(2, 0), tl::BitRow(2, 0)});
  for (auto& term : terms)
    for (int l = 0; l < 3; ++l) {
      const std::size_t i = rng() % n;
      term.care[i / 64] |= std::uint64_t{1} << (i % 64);
      if (rng() & 1) term.value[i / 64] |= std::uint64_t{1} << (i % 64);
    }
  tl::TruthTable t{n, {}, {}};
  while (t.on.size() < 2000 || t.off.size() < 2000) {
    tl::BitRow m{rng(), rng() & ((std::uint64_t{1} << 36) - 1)};
    bool inside = false;
    for (const auto& term : terms) inside = inside || term.contains(m);
    auto& set = inside ? t.on : t.off;
    if (set.size() < 2000) set.push_back(m);
  }
  const auto start = std::chrono::steady_clock::now();
  const tl::Cover cover = tl::espresso(t);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::size_t literals = 0;
  for (const auto& cube : cover) literals += cube.literal_count();
  std::printf("wide espresso: %zu cubes, %zu literals, %.1f ms\n", cover.size(), literals, ms);
  EXPECT_TRUE(tl::covers_exactly(t, cover));
}

TEST(TwoLevel, RefusesBadTables) {
  tl::TruthTable both{2, {{1}, {2}}, {{2}}};
  EXPECT_THROW(tl::espresso(both), std::invalid_argument);
  tl::TruthTable wide{2, {{4}}, {}};
  EXPECT_THROW(tl::deduplicated(wide), std::invalid_argument);
  tl::TruthTable big{17, {{1}}, {{0}}};
  EXPECT_THROW(tl::quine_mccluskey(big), std::length_error);
}

TEST(TwoLevel, EdgeCases) {
  const tl::TruthTable empty{4, {}, {{3}}};
  EXPECT_TRUE(tl::espresso(empty).empty());
  EXPECT_TRUE(tl::quine_mccluskey(empty).empty());
  const tl::TruthTable all_on{4, {{3}, {5}}, {}};
  EXPECT_EQ(tl::espresso(all_on).size(), 1u);
  EXPECT_EQ(tl::espresso(all_on)[0].literal_count(), 0u);
  EXPECT_EQ(tl::set_cover_minimise(all_on, false, 3).size(), 1u);
}
