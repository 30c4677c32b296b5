// Internal to construct/: the labelled cells turned into one level of a designer's tree,
// envelope & (positives - holes), each positive and hole a product of halfspaces (a box, a
// cylinder with its caps, a box less a cylinder).
//
// Seed 001's dominant halfspaces give the envelope: every halfspace the whole solid lies in
// (the bounding faces). Inside it, each hole is grown from a cell of empty samples to the
// largest product of halfspaces that holds no solid sample, and each positive from a cell of
// solid samples to the largest product that holds no empty sample except inside holes it pays
// for; a greedy weighted set cover then picks the positives (and the holes they need) that
// cover the solid with the fewest primitives.
#pragma once

#include <chrono>
#include <vector>

#include "literals.h"
#include "samples.h"

namespace csgfit::construct {

/// A halfspace on one of its sides.
struct Term {
  int literal = 0;
  bool inside = true;
  bool operator==(const Term& o) const { return literal == o.literal && inside == o.inside; }
};

/// The intersection of its terms.
using Product = std::vector<Term>;

struct Cover {
  Product envelope;
  std::vector<Product> positives, holes;
  /// Solid samples no positive covers and empty ones a positive covers that no hole takes
  /// away: what the construction leaves wrong (weighted as Samples counts).
  double missed = 0, extra = 0;
  double solid_weight = 0;
};

/// Every literal's column of the samples, computed once.
struct Cells {
  const Samples* samples = nullptr;
  const std::vector<Literal>* literals = nullptr;
  std::vector<Column> columns;
};

Cells cells_of(const Samples& samples, const std::vector<Literal>& literals);

/// The samples inside the product (and not padding).
Column coverage(const Product& p, const Cells& cells);

/// The construction's cover of the labelled samples. Stops early at the deadline (what is not
/// covered then is missed).
Cover cover_cells(const Cells& cells, std::chrono::steady_clock::time_point deadline);

/// Primitives the product becomes when written: a box per frame of its planes (halfspaces
/// along the model axes count as one box), one per curved halfspace.
double product_cost(const Product& p, const std::vector<Literal>& literals);

}  // namespace csgfit::construct
