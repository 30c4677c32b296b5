#include "csgfit/seed/boundary_rectangles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "csgfit/features/boundary_walls.h"

namespace csgfit {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

// An interval of p . n between a wall facing -n (at -lo) and one facing n (at hi).
struct Slab {
  double lo = 0, hi = 0;
  bool inside(const Slab& o, double tol) const { return lo >= o.lo - tol && hi <= o.hi + tol; }
};

std::vector<Slab> slabs(const std::vector<BoundaryWall>& facing_n, const std::vector<BoundaryWall>& facing_back,
                        std::size_t strongest) {
  std::vector<Slab> out;
  for (std::size_t i = 0; i < std::min(strongest, facing_back.size()); ++i)
    for (std::size_t j = 0; j < std::min(strongest, facing_n.size()); ++j) {
      const Slab s{-facing_back[i].offset, facing_n[j].offset};
      if (s.hi - s.lo >= 2) out.push_back(s);
    }
  return out;
}

// The pixels of r, and those of them outside `target`, counted on r's rows only: a canvas-wide
// count per candidate would cost the whole image ten thousand times a family.
struct Coverage {
  std::size_t area = 0, outside = 0;
};

// Counting stops once more than `allowed` pixels are outside: most candidates fail early.
Coverage coverage(const Primitive& r, const Bitmap& target, Bitmap& scratch, double allowed) {
  int begin = 0, end = 0;
  row_range(r, target.height(), begin, end);
  for (int row = begin; row < end; ++row) std::fill_n(scratch.row_words(row), scratch.words_per_row(), 0);
  rasterize_into(r, scratch);
  Coverage c;
  for (int row = begin; row < end; ++row) {
    const std::uint64_t* drawn = scratch.row_words(row);
    const std::uint64_t* shape = target.row_words(row);
    for (int w = 0; w < target.words_per_row(); ++w) {
      c.area += static_cast<std::size_t>(__builtin_popcountll(drawn[w]));
      c.outside += static_cast<std::size_t>(__builtin_popcountll(drawn[w] & ~shape[w]));
    }
    if (static_cast<double>(c.outside) > allowed) break;
  }
  return c;
}

struct Found {
  Primitive rectangle;
  Slab along, across;
  std::size_t family = 0;
};

}  // namespace

std::vector<Primitive> boundary_rectangles(const Bitmap& target, std::size_t limit, double excess,
                                           const Bitmap* drilled) {
  const std::vector<WallFamily> families = boundary_walls(target);
  Bitmap plate = target;
  if (drilled) plate |= *drilled;
  Bitmap drawn(target.width(), target.height());
  std::vector<Found> found;
  for (std::size_t f = 0; f < families.size(); ++f) {
    const WallFamily& fam = families[f];
    const double c = std::cos(fam.angle * kDeg), s = std::sin(fam.angle * kDeg);
    // Ten walls a side bound the work to 10^4 rectangles a family.
    const std::vector<Slab> along = slabs(fam.walls[0], fam.walls[2], 10);
    const std::vector<Slab> across = slabs(fam.walls[1], fam.walls[3], 10);
    for (const Slab& a : along)
      for (const Slab& b : across) {
        const double u = 0.5 * (a.lo + a.hi), v = 0.5 * (b.lo + b.hi);
        const Primitive r = Primitive::rectangle(u * c - v * s, u * s + v * c, a.hi - a.lo, b.hi - b.lo, fam.angle);
        const Coverage cov = coverage(r, plate, drawn, excess * r.area() + 2);
        if (cov.area < 4 || static_cast<double>(cov.outside) > excess * static_cast<double>(cov.area)) continue;
        found.push_back({r, a, b, f});
      }
  }
  std::vector<Primitive> out;
  for (const Found& r : found) {
    const bool inside_another = std::any_of(found.begin(), found.end(), [&](const Found& o) {
      return &o != &r && o.family == r.family && r.along.inside(o.along, 0.5) && r.across.inside(o.across, 0.5) &&
             o.rectangle.area() > r.rectangle.area() + 1e-9;
    });
    // Walls split by a ragged edge give the same rectangle twice.
    const bool seen = std::any_of(out.begin(), out.end(), [&](const Primitive& o) {
      return std::fabs(o.cx - r.rectangle.cx) < 1 && std::fabs(o.cy - r.rectangle.cy) < 1 &&
             std::fabs(o.w - r.rectangle.w) < 1.5 && std::fabs(o.h - r.rectangle.h) < 1.5 &&
             std::fabs(o.angle - r.rectangle.angle) < 1;
    });
    if (!inside_another && !seen) out.push_back(r.rectangle);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Primitive& p, const Primitive& q) { return p.area() > q.area(); });
  if (out.size() > limit) out.resize(limit);
  return out;
}

}  // namespace csgfit
