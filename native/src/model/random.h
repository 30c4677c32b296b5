// Internal: the random numbers the searches and the surface sampling draw, reproducible across
// compilers and standard libraries (std::*_distribution are not), so a seed means one tree.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

namespace csgfit::rnd {

using Rng = std::mt19937_64;

/// Spreads a (seed, island) pair over the generator's state space.
inline std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline double uniform(Rng& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

/// Box-Muller on our own uniforms.
inline double normal(Rng& rng, double mean, double sd) {
  const double u1 = std::max(uniform(rng, 0, 1), 1e-300), u2 = uniform(rng, 0, 1);
  return mean + sd * std::sqrt(-2 * std::log(u1)) * std::cos(2 * 3.14159265358979323846 * u2);
}

/// An index in [0, n).
inline std::size_t pick(Rng& rng, std::size_t n) { return static_cast<std::size_t>(rng() % n); }

/// Seed 000's norm(a, s) for subtree sizes: a normal draw rounded, at least 1.
inline int norm_count(Rng& rng, double mean, double sd) {
  return std::max(1, static_cast<int>(std::lround(normal(rng, mean, sd))));
}

}  // namespace csgfit::rnd
