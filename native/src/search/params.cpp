#include "csgfit/search/params.h"

#include <stdexcept>
#include <string>

namespace csgfit {

SearchParams SearchParams::paper() {
  SearchParams p;
  p.population = 500;
  p.max_trees = 5000;
  p.max_stale = 500;
  p.refocus_interval = 50;
  p.initial_size_mean = 10;
  p.initial_size_sd = 2;
  p.added_size_mean = 3;
  p.added_size_sd = 1.5;
  p.local_iterations = 80;
  p.seed_with_decomposition = false;
  p.k_at_128 = 25;
  return p;
}

SearchParams SearchParams::for_3d() {
  SearchParams p;
  p.max_trees = 1 << 30;
  p.max_stale = 600;
  p.refocus_interval = 0;
  p.generation = 4;
  p.migration = Migration::BestToStuckest;
  p.accept_margin = 1e-9;
  // ADD matches a primitive to what the tree gets wrong, so it does most of the work.
  p.odds = OperatorOdds{0.15, 0.47, 0.2, 0.15, 0.03};
  return p;
}

SearchParams SearchParams::for_morph(const std::string& preset) {
  if (preset == "paper") {
    SearchParams p = paper();
    p.initial_size_mean = 5;  // the paper's morphing runs: simpler shapes, smaller trees
    return p;
  }
  if (preset == "default") {
    SearchParams p;
    p.initial_size_mean = 5;
    p.k_at_128 = 25;  // as the paper's pairs: fewer primitives morph more legibly
    return p;
  }
  throw std::invalid_argument("unknown preset '" + preset + "' (expected default or paper)");
}

SearchParams SearchParams::for_quality(const std::string& name) {
  if (name == "paper") return paper();
  SearchParams p;
  if (name == "default") return p;
  if (name == "fast") {
    p.population = 8;
    p.max_stale = 1500;
    return p;
  }
  if (name == "best") {
    p.population = 48;
    p.max_stale = 20000;
    return p;
  }
  throw std::invalid_argument("unknown quality '" + name + "' (expected fast, default, best or paper)");
}

}  // namespace csgfit
