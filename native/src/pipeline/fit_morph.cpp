// Two shapes -> a pair of trees of one structure (seed 000's morphing): each target's problem,
// the first pairs, the pair search, the polish, the primitives seen in one shape only.
#include "csgfit/pipeline/fit_morph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "csgfit/error.h"
#include "csgfit/model/voxelize.h"
#include "pipeline/fit_request.h"
#include "pipeline/morph_search.h"
#include "pipeline/problems.h"

namespace csgfit {

namespace {

using Clock = std::chrono::steady_clock;

template <typename Dim>
using Pair = morph::PairCandidate<Dim>;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Every leaf of a first tree is new to the other target.
template <typename Tree>
auto all_leaves(const Tree& t) {
  std::vector<std::decay_t<decltype(*leaves(t).front())>> out;
  for (const auto* p : leaves(t)) out.push_back(*p);
  return out;
}

// A first tree copied into both trees of a pair, each copy optimised against its own target,
// then pruned in pairs.
template <typename Dim>
void add_copies(morph::PairOperators<Dim>& maker, const typename Dim::Tree& tree,
                std::vector<Pair<Dim>>& first) {
  if (tree.primitive_count() == 0) return;
  Pair<Dim> c = maker.copies(tree, all_leaves(tree));
  if (!std::isfinite(c.score)) return;
  maker.accept(c);
  first.push_back(std::move(c));
}

template <typename Dim>
Pair<Dim> unknown_pair() {
  Pair<Dim> c;
  c.score = std::numeric_limits<double>::infinity();
  return c;
}

void check_targets(const Bitmap& a, const Bitmap& b, const FitOptions& options) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument("the two images differ in size (" + std::to_string(a.width()) + " x " +
                                std::to_string(a.height()) + " and " + std::to_string(b.width()) +
                                " x " + std::to_string(b.height()) + " pixels)");
  for (const Bitmap* t : {&a, &b})
    if (t->count() == 0)
      throw std::invalid_argument(std::string("no shape found in image ") + (t == &a ? "A" : "B"));
  check_fit_request(a, options.primitives, options.time_limit);
}

// A pair's primitive is drawn in both shapes, so each tree is charged half the size weight:
// the mean of the two scores then charges k once per primitive of the pair, and a primitive
// that only one shape needs pays as it would in that shape's own fit (with a full k in each
// tree it had to explain 2k pixels, and the ends fell 0.02-0.04 IoU behind the own fits).
template <typename Problem>
Problem halved_k(Problem pb) {
  pb.k *= 0.5;
  return pb;
}

bool same_lattice(const VoxelGrid& a, const VoxelGrid& b) {
  return a.nx() == b.nx() && a.ny() == b.ny() && a.nz() == b.nz() &&
         a.origin_x() == b.origin_x() && a.origin_y() == b.origin_y() &&
         a.origin_z() == b.origin_z() && a.voxel_size() == b.voxel_size();
}

std::string grid_size(const VoxelGrid& g) {
  return std::to_string(g.nx()) + " x " + std::to_string(g.ny()) + " x " + std::to_string(g.nz());
}

}  // namespace

std::pair<VoxelGrid, VoxelGrid> morph_grids(const Input3D& a, const Input3D& b, int resolution) {
  if (a.is_mesh() != b.is_mesh()) throw InputError("give two meshes or two voxel grids, not one of each");
  if (!a.is_mesh()) {
    if (!same_lattice(a.voxels, b.voxels))
      throw InputError("the voxel grids differ: " + grid_size(a.voxels) + " and " + grid_size(b.voxels) +
                       " voxels (or their origin or voxel size)");
    return {a.voxels, b.voxels};
  }
  VoxelizeOptions vo;
  vo.cover_box = true;
  vo.box_lo.fill(std::numeric_limits<double>::infinity());
  vo.box_hi.fill(-std::numeric_limits<double>::infinity());
  for (const TriangleMesh* m : {&a.mesh, &b.mesh})
    for (const auto& v : m->vertices)
      for (int i = 0; i < 3; ++i) {
        vo.box_lo[i] = std::min(vo.box_lo[i], v[i]);
        vo.box_hi[i] = std::max(vo.box_hi[i], v[i]);
      }
  const double longest = std::max({vo.box_hi[0] - vo.box_lo[0], vo.box_hi[1] - vo.box_lo[1],
                                   vo.box_hi[2] - vo.box_lo[2]});
  vo.voxel_size = longest / (resolution > 0 ? resolution : 64);
  if (!(vo.voxel_size > 0)) throw InputError("the two meshes have no extent");
  return {voxelize(a.mesh, vo), voxelize(b.mesh, vo)};
}

MorphResult morph_bitmaps(const Bitmap& a, const Bitmap& b, const MorphOptions& options,
                          const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  using Dim = morph::Dim2D;
  const auto start = Clock::now();
  const FitOptions& fo = options.fit;
  check_search_options(fo.time_limit, fo.threads, fo.k);
  check_targets(a, b, fo);
  const Problem2D pa = halved_k(make_problem2d(a, fo, start)), pb = halved_k(make_problem2d(b, fo, start));
  const morph::PairProblem<Dim> problem{&pa, &pb, fo.search};

  const int count = std::min(islands::island_count(fo.threads), std::max(1, fo.search.population));
  const std::size_t per_island = static_cast<std::size_t>(std::max(2, fo.search.population / count));
  std::size_t evaluations = 0;
  std::vector<Pair<Dim>> first;
  if (fo.search.seed_with_decomposition) {
    Operators2D oa(pa, fo.seed), ob(pb, fo.seed);
    const SeedTrees2D sa = seed_trees2d(a, fo, pa, oa, start, evaluations);
    const SeedTrees2D sb = seed_trees2d(b, fo, pb, ob, start, evaluations);
    evaluations += oa.evaluations + ob.evaluations;
    morph::PairOperators<Dim> maker(problem, fo.seed);
    for (const Candidate2D* c : {&sa.decomposition, &sb.decomposition, &sa.greedy, &sb.greedy})
      add_copies(maker, c->tree, first);
    evaluations += maker.evaluations;
  }
  auto isles = morph::first_populations<Dim>(problem, first, fo.seed, count, per_island);

  const islands::Limits limits{start, fo.time_limit, 0.9 * fo.time_limit, cancel, progress};
  const auto found =
      islands::search<morph::PairOperators<Dim>>(isles, unknown_pair<Dim>(), fo.search, limits, evaluations, nullptr);
  evaluations += found.evaluations;
  LocalOptOptions lo = LocalOptOptions::pattern(fo.search.local_iterations, 0.5, 1.0 / 32);
  lo.deadline = at_fraction(start, fo.time_limit, 1.0);
  const std::size_t before = isles[0].ops.evaluations;
  const Pair<Dim> best = morph::polish_pair(isles[0].ops, problem, found.best, lo);
  evaluations += isles[0].ops.evaluations - before;

  MorphResult out;
  morph::fill_result(out, best, problem, found, evaluations, seconds_since(start));
  choose_turns(out.a, out.b, options.rotate);
  out.width = a.width();
  out.height = a.height();
  return out;
}

MorphResult3D morph_voxels(const VoxelGrid& a, const VoxelGrid& b, const FitOptions3D& options,
                           const ProgressCallback& progress, const std::atomic<bool>* cancel) {
  using Dim = morph::Dim3D;
  const auto start = Clock::now();
  check_search_options(options.time_limit, options.threads, options.k);
  if (!same_lattice(a, b))
    throw std::invalid_argument("the two voxel grids of a morph must share their lattice (size, origin, voxel edge)");
  for (const VoxelGrid* t : {&a, &b})
    if (t->count() == 0)
      throw std::invalid_argument(std::string("no shape found in input ") + (t == &a ? "A" : "B"));
  check_fit_request(a, options.primitives, options.time_limit);
  if (!options.primitives.has(PrimitiveKind3D::Box))
    throw std::invalid_argument("the 3D morph needs boxes among the primitives");
  const Problem3D pa = halved_k(make_problem3d(a, options, start, cancel));
  const Problem3D pb = halved_k(make_problem3d(b, options, start, cancel));
  const morph::PairProblem<Dim> problem{&pa, &pb, options.search};

  // Each first tree gets half of what a single fit's does.
  FitOptions3D half = options;
  half.time_limit = 0.5 * options.time_limit;
  std::size_t evaluations = 0;
  std::vector<Pair<Dim>> first;
  morph::PairOperators<Dim> maker(problem, options.seed);
  add_copies(maker, first_tree3d(a, half, pa, start, cancel, evaluations), first);
  add_copies(maker, first_tree3d(b, half, pb, start, cancel, evaluations), first);
  evaluations += maker.evaluations;
  if (first.empty()) throw std::invalid_argument("seed 003 found no primitive for either shape");
  auto isles = morph::first_populations<Dim>(problem, first, options.seed,
                                             islands::island_count(options.threads), 1);
  Pair<Dim> known = first.front();
  for (const Pair<Dim>& c : first)
    if (c.score < known.score) known = c;

  const islands::Limits limits{start, options.time_limit, 0.85 * options.time_limit, cancel, progress};
  const auto found = islands::search<morph::PairOperators<Dim>>(isles, known, options.search, limits, evaluations, nullptr);
  evaluations += found.evaluations;
  LocalOptOptions lo = LocalOptOptions::pattern(20, 0.5, 1.0 / 16);
  lo.deadline = at_fraction(start, options.time_limit, 1.0);
  lo.cancel = cancel;
  const std::size_t before = isles[0].ops.evaluations;
  const Pair<Dim> best = morph::polish_pair(isles[0].ops, problem, found.best, lo);
  evaluations += isles[0].ops.evaluations - before;

  MorphResult3D out;
  morph::fill_result(out, best, problem, found, evaluations, seconds_since(start));
  return out;
}

}  // namespace csgfit
