// Rectangles read off the boundary's straight edges: proposals for the first trees that carry
// the orientation and sizes the designer drew, which a distance peak does not.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/model/bitmap.h"
#include "csgfit/model/primitive2d.h"

namespace csgfit {

/// Rectangles whose four sides lie on walls of `target`'s boundary (two parallel pairs of one
/// wall family, see boundary_walls) and that lie inside the shape but for `excess` of their
/// area; only the maximal ones (none inside another of its family), largest first, at most
/// `limit`. A bar of a cross or a star is one such rectangle at its true angle. `drilled`, when
/// given, holds the pixels of holes already read off the boundary: a plate may cover them, as
/// the designer's plate did before its holes were cut.
std::vector<Primitive> boundary_rectangles(const Bitmap& target, std::size_t limit = 48,
                                           double excess = 0.03, const Bitmap* drilled = nullptr);

}  // namespace csgfit
