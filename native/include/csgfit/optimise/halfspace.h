// What the optimiser knows of a halfspace (seed 001's primitives): its bounds and an
// inside test. The leaves' own types (our primitives, OpenSCAD calls under a matrix) stay with
// the caller; the optimiser sees only this, in 2D and 3D alike.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

namespace csgfit::opt {

template <std::size_t D>
using Point = std::array<double, D>;

template <std::size_t D>
struct Box {
  Point<D> lo{}, hi{};
  bool contains(const Point<D>& p) const {
    for (std::size_t a = 0; a < D; ++a)
      if (p[a] < lo[a] || p[a] > hi[a]) return false;
    return true;
  }
  bool overlaps(const Box& o) const {
    for (std::size_t a = 0; a < D; ++a)
      if (o.hi[a] < lo[a] || o.lo[a] > hi[a]) return false;
    return true;
  }
  void include(const Box& o) {
    for (std::size_t a = 0; a < D; ++a) lo[a] = std::min(lo[a], o.lo[a]), hi[a] = std::max(hi[a], o.hi[a]);
  }
};

/// One halfspace: a bounded solid (every primitive we write is bounded) with an inside test.
template <std::size_t D>
struct Halfspace {
  Box<D> bounds;  ///< holds every inside point
  std::function<bool(const Point<D>&)> contains;
};

template <std::size_t D>
using HalfspaceList = std::vector<Halfspace<D>>;

}  // namespace csgfit::opt
