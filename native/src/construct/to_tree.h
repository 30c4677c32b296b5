// Internal to construct/: the cover written as our tree: each product's planes along the model
// axes one box, other parallel planes a slab, each curved halfspace its primitive cut to the
// product's extent (a cylinder takes the caps across its axis as its own ends), the envelope
// only where a positive would reach out of it.
#pragma once

#include <optional>

#include "cover.h"
#include "csgfit/model/tree3d.h"

namespace csgfit::construct {

/// The tree of envelope & (union of positives - holes) over `domain` (the box of the samples);
/// none without positives.
std::optional<Node3D> tree_of(const Cover& cover, const std::vector<Literal>& literals, const Bounds3& domain);

}  // namespace csgfit::construct
