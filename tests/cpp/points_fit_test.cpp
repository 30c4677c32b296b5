// Seed 004 on point clouds: the fitness on hand-made configurations, the curvature types, the
// GP operators keeping trees valid, the same seed giving the same tree, and bad clouds refused.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "csgfit/error.h"
#include "csgfit/pipeline/fit_points.h"
#include "csgfit/refine/nurbs_fit.h"
#include "pipeline/height_levels.h"
#include "search/gp_operators.h"
#include "search/untie_points.h"

using namespace csgfit;

namespace {

// Points on the surface of an axis-aligned box, n per unit of area roughly, normals outward.
void box_surface(const Vec3& lo, const Vec3& hi, double step, std::vector<Vec3>& pts,
                 std::vector<Vec3>& nrm, bool with_bottom = true) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      if (axis == 2 && side == 0 && !with_bottom) continue;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (double u = lo[a] + step / 2; u < hi[a]; u += step)
        for (double v = lo[b] + step / 2; v < hi[b]; v += step) {
          Vec3 p{}, n{};
          p[axis] = side ? hi[axis] : lo[axis];
          p[a] = u, p[b] = v;
          n[axis] = side ? 1 : -1;
          pts.push_back(p);
          nrm.push_back(n);
        }
    }
}

PointTarget box_target(ScanKind scan) {
  std::vector<Vec3> p, n;
  if (scan == ScanKind::All) {
    box_surface({0, 0, 0}, {10, 6, 4}, 0.5, p, n);
  } else {
    for (double x = 0.25; x < 10; x += 0.5)
      for (double y = 0.25; y < 6; y += 0.5) p.push_back({x, y, 4}), n.push_back({0, 0, 1});
  }
  return make_point_target(p, n, scan, 0);
}

const Primitive3D kBox = Primitive3D::box(5, 3, 2, 10, 6, 4);

}  // namespace

TEST(PointFitness, TheRightBoxScoresBestAllAround) {
  const PointTarget t = box_target(ScanKind::All);
  const FitnessWeights w;
  const FitnessTerms exact = point_fitness(Node3D::leaf(kBox), t, w);
  EXPECT_GT(exact.distance, 0.999);
  EXPECT_GT(exact.normals, 0.95);  // the central differences blend faces at the edges
  EXPECT_NEAR(exact.mean_distance, 0, 1e-9);
  const FitnessTerms moved = point_fitness(Node3D::leaf(Primitive3D::box(5.5, 3, 2, 10, 6, 4)), t, w);
  EXPECT_LT(moved.fitness, exact.fitness);
  // A second primitive that changes nothing costs its nodes.
  const Node3D more = Node3D::op(NodeKind::Union, {Node3D::leaf(kBox), Node3D::leaf(Primitive3D::sphere(5, 3, 2, 1))});
  EXPECT_NEAR(point_fitness(more, t, w).fitness, exact.fitness - 2 * w.node_cost, 1e-9);
}

TEST(PointFitness, ScanFromAboveMeasuresAlongZAndSeesTheFloor) {
  const PointTarget t = box_target(ScanKind::Top);
  EXPECT_FALSE(t.floor_samples.empty());  // the table around the part
  const FitnessWeights w;
  const FitnessTerms exact = point_fitness(Node3D::leaf(kBox), t, w);
  EXPECT_GT(exact.distance, 0.999);
  EXPECT_DOUBLE_EQ(exact.floor, 1.0);
  // Along z a thin plate at the top is as good as the block: only the z-ray counts ...
  const FitnessTerms plate = point_fitness(Node3D::leaf(Primitive3D::box(5, 3, 3.9, 10, 6, 0.2)), t, w);
  EXPECT_NEAR(plate.distance, exact.distance, 1e-9);
  // ... but a block spilling over the table is not.
  const FitnessTerms wide = point_fitness(Node3D::leaf(Primitive3D::box(5, 3, 2, 16, 6, 4)), t, w);
  EXPECT_LT(wide.floor, 0.9);
  EXPECT_LT(wide.fitness, exact.fitness);
}

TEST(PointFitness, GroundingStandsAPlateOnTheFloor) {
  const PointTarget t = box_target(ScanKind::Top);
  Node3D tree = Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::box(5, 3, 3.9, 10, 6, 0.2)),
                                                 Node3D::leaf(Primitive3D::cylinder(5, 3, 3, 1, 1))});
  gp::ground(tree, t);
  const Primitive3D& plate = tree.children[0].primitive;
  EXPECT_NEAR(plate.cz - plate.dims[2] / 2, 0, 1e-12);
  EXPECT_NEAR(plate.cz + plate.dims[2] / 2, 4, 1e-12);
  const Primitive3D& hole = tree.children[1].primitive;
  EXPECT_NEAR(hole.cz - hole.dims[2] / 2, 2.5, 1e-12);  // its bottom stays; its top opens up
  EXPECT_GT(hole.cz + hole.dims[2] / 2, 4);
}

TEST(PointCurvature, SphereConvexCavityConcavePlaneFlat) {
  std::vector<Vec3> p, out, in;
  for (int i = 0; i < 2000; ++i) {
    // A Fibonacci sphere of radius 5.
    const double z = 1 - 2 * (i + 0.5) / 2000, r = std::sqrt(1 - z * z), a = 2.399963 * i;
    const Vec3 n{r * std::cos(a), r * std::sin(a), z};
    p.push_back({5 * n[0], 5 * n[1], 5 * n[2]});
    out.push_back(n);
    in.push_back({-n[0], -n[1], -n[2]});
  }
  int convex = 0, concave = 0;
  for (CurvatureType c : curvature_types(p, out, 100)) convex += c == CurvatureType::Convex;
  for (CurvatureType c : curvature_types(p, in, 100)) concave += c == CurvatureType::Concave;
  EXPECT_GT(convex, 1900);
  EXPECT_GT(concave, 1900);
  std::vector<Vec3> plane, up;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) plane.push_back({i * 0.5, j * 0.5, 1}), up.push_back({0, 0, 1});
  for (CurvatureType c : curvature_types(plane, up, 30)) EXPECT_EQ(c, CurvatureType::Flat);
}

TEST(GpOperators, EveryVariationKeepsTheTreeValid) {
  const PointTarget t = box_target(ScanKind::All);
  const std::vector<std::size_t> subset;
  const gp::Context c{&t, &subset, PrimitiveSet3D::parse("box,sphere,cylinder,cone"), nullptr, 0.05};
  rnd::Rng rng(7);
  GpIndividual a{Node3D::leaf(kBox), {0.05}, 0}, b = a;
  for (int step = 0; step < 400; ++step) {
    GpIndividual g = step % 2 ? a : b;
    switch (step % 6) {
      case 0: gp::insert_terminal(g, c, rng); break;
      case 1: gp::delete_subtree(g, rng); break;
      case 2: gp::mutate_relation(g, rng); break;
      case 3: gp::replace_terminal(g, c, rng); break;
      case 4: g = gp::exchange_subtrees(a, b, rng); break;
      default: gp::mutate_terminals(g, c, rng); break;
    }
    if (!gp::tidy(g, c)) continue;
    ASSERT_GT(g.tree.primitive_count(), 0u);
    ASSERT_EQ(g.sigma.size(), leaves(g.tree).size());
    for (const Primitive3D* p : leaves(g.tree)) {
      ASSERT_TRUE(std::isfinite(p->cx + p->cy + p->cz + p->dims[0] + p->dims[1] + p->dims[2]));
      ASSERT_GT(p->volume(), 0);
    }
    (step % 2 ? a : b) = std::move(g);
  }
}

TEST(GpSearch, SameSeedSameTree) {
  const PointTarget t = box_target(ScanKind::All);
  GpParams params;
  params.max_generations = 6;
  params.time_limit = 1e6;
  params.islands = 3;
  params.seed = 11;
  const GpResult one = run_gp(t, params, {}, nullptr);
  const GpResult two = run_gp(t, params, {}, nullptr);
  EXPECT_EQ(one.generations, 6u);
  EXPECT_TRUE(one.tree == two.tree);
  EXPECT_EQ(one.terms.fitness, two.terms.fitness);
  params.seed = 12;
  EXPECT_FALSE(run_gp(t, params, {}, nullptr).tree == one.tree);
}

TEST(GpSearch, ImprovesOnItsDetectedStart) {
  const PointTarget t = box_target(ScanKind::All);
  GpParams params;
  params.max_generations = 20;
  params.time_limit = 1e6;
  const Node3D near = Node3D::leaf(Primitive3D::box(5.3, 2.8, 2.1, 9.5, 6.4, 4.2));
  const GpResult r = run_gp(t, params, {near}, nullptr);
  const FitnessTerms start = point_fitness(near, t, params.weights);
  EXPECT_GE(r.terms.fitness, start.fitness);
  EXPECT_LT(r.terms.mean_distance, 0.5 * start.mean_distance);
}

namespace {

// A part seen from above on a 0.4 mm grid: the top of `solid` in each column (its highest
// point in 0 .. 20 mm), normals up where flat and from the neighbouring heights elsewhere.
template <class Solid>
PointTarget top_scan(Solid solid, double sx, double sy) {
  std::vector<Vec3> pts, nrm;
  const auto top = [&](double x, double y) {
    for (double z = 20; z > 0; z -= 0.01)
      if (solid(x, y, z)) return z;
    return 0.0;
  };
  for (double x = 0.2; x < sx; x += 0.4)
    for (double y = 0.2; y < sy; y += 0.4) {
      const double z = top(x, y);
      if (z <= 0) continue;
      const double zx = (top(x + 0.05, y) - top(x - 0.05, y)) / 0.1, zy = (top(x, y + 0.05) - top(x, y - 0.05)) / 0.1;
      const double len = std::sqrt(zx * zx + zy * zy + 1);
      pts.push_back({x, y, z});
      nrm.push_back(std::fabs(zx) + std::fabs(zy) > 5 ? Vec3{0, 0, 1} : Vec3{-zx / len, -zy / len, 1 / len});
    }
  return make_point_target(pts, nrm, ScanKind::Top, 0);
}

// Volume IoU of a tree against a solid on a 0.25 mm grid over [0, sx] x [0, sy] x [0, 20].
template <class Solid>
double volume_iou(const Node3D& tree, Solid solid, double sx, double sy) {
  double both = 0, either = 0;
  for (double x = 0.125; x < sx; x += 0.25)
    for (double y = 0.125; y < sy; y += 0.25)
      for (double z = 0.125; z < 20; z += 0.25) {
        const bool a = contains(tree, x, y, z), b = solid(x, y, z);
        both += a && b, either += a || b;
      }
  return both / either;
}

}  // namespace

// A plate with a boss and a pocket (levels 10, 16 and 5): each level's footprint, fitted in
// 2D and extruded, rebuilds the part before any search.
TEST(HeightLevels, FootprintsOfTheLevelsRebuildABlockPart) {
  const auto part = [](double x, double y, double z) {
    const bool plate = x <= 40 && y <= 24 && z <= 10;
    const bool boss = std::hypot(x - 10, y - 12) <= 5 && z <= 16;
    const bool pocket = x >= 24 && x <= 34 && y >= 7 && y <= 17 && z >= 5;
    return (plate || boss) && !pocket;
  };
  const PointTarget t = top_scan(part, 40, 24);
  LevelOptions o;
  o.seconds = 3;
  o.threads = 1;
  const std::vector<Node3D> trees = level_trees(t, {}, o, nullptr);
  ASSERT_EQ(trees.size(), 1u);  // no curved hole: no second tree
  EXPECT_GT(volume_iou(trees[0], part, 40, 24), 0.95);
  EXPECT_LE(trees[0].primitive_count(), 6u);
  // Without boxes or cylinders to extrude there is no footprint to fit.
  o.primitives = PrimitiveSet3D::parse("sphere");
  EXPECT_TRUE(level_trees(t, {}, o, nullptr).empty());
}

// A dimple's hole is filled in its level's footprint (its bottom is curved), and the second
// tree cuts the sphere a detected tree subtracts; the first has none.
TEST(HeightLevels, ACurvedHoleTakesTheDetectedSphere) {
  const auto part = [](double x, double y, double z) {
    return x <= 30 && y <= 30 && z <= 15 && std::hypot(x - 15, y - 15, z - 19) > 10;
  };
  const PointTarget t = top_scan(part, 30, 30);
  const Node3D detected = Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::box(15, 15, 7.5, 30, 30, 15)),
                                                            Node3D::leaf(Primitive3D::sphere(15, 15, 19, 10))});
  LevelOptions o;
  o.seconds = 2;
  o.threads = 1;
  const std::vector<Node3D> trees = level_trees(t, {detected}, o, nullptr);
  ASSERT_EQ(trees.size(), 2u);
  EXPECT_EQ(trees[0].primitive_count(), 1u);  // the filled footprint: one block
  EXPECT_GT(volume_iou(trees[1], part, 30, 30), 0.95);  // a first tree: the search polishes it
  EXPECT_GT(volume_iou(trees[1], part, 30, 30), volume_iou(trees[0], part, 30, 30));
}

TEST(NurbsFit, RecoversAPatchFromItsOwnSamples) {
  std::vector<double> h;
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 7; ++i) h.push_back(3 + std::sin(i) + 0.5 * j);
  const BSplineSurface truth = BSplineSurface::height_field(BSplineBasis(7, 3), BSplineBasis(5, 3), {0, 40, 0, 30}, h);
  std::vector<Vec3> pts;
  for (int j = 0; j <= 30; ++j)
    for (int i = 0; i <= 40; ++i) pts.push_back({double(i), double(j), truth.height_at(i, j)});
  const PatchFit f = fit_height_patch(pts, 0);
  EXPECT_LT(f.rms, 1e-4);
  for (double x : {3.3, 20.0, 37.1})
    EXPECT_NEAR(f.terminal.patch->height_at(x - 20, 10.7 - 15), truth.height_at(x, 10.7), 1e-3);
}

// The seed's sparse blade: 8 x 24 samples of a net drawn with equally spaced columns. A
// Greville net bends between the sample rows where the true surface does not; the held-out
// points choose the spacing, and the surface between the rows comes back.
TEST(NurbsFit, ChoosesEquallySpacedColumnsWhenThePointsSayso) {
  std::vector<double> h;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 12; ++i) h.push_back(10 + 2 * std::sin(0.9 * i) - 0.8 * j);
  const BSplineSurface truth = BSplineSurface::height_field(BSplineBasis(12, 3), BSplineBasis(4, 3),
                                                            {0, 60, 0, 20}, h, NetSpacing::Uniform);
  std::vector<Vec3> pts;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 24; ++i) {
      const double x = 60.0 * i / 23, y = 20.0 * j / 7;
      pts.push_back({x, y, truth.height_at(x, y)});
    }
  const PatchFit f = fit_height_patch(pts, 0);
  EXPECT_EQ(f.spacing, NetSpacing::Uniform);
  double worst = 0;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 120; ++i) {
      const double x = 0.5 * i, y = 0.5 * j;
      worst = std::max(worst, std::abs(f.terminal.patch->height_at(x - 30, y - 10) - truth.height_at(x, y)));
    }
  EXPECT_LT(worst, 0.01);
}

namespace {

std::string fit_error(std::vector<Vec3> pts, std::vector<Vec3> nrm, std::optional<ScanKind> scan = {}) {
  RangeScan s;
  s.source = "cloud.xyz";
  s.points = std::move(pts);
  s.normals = std::move(nrm);
  PointsFitOptions o;
  o.scan = scan;
  o.max_generations = 1;
  try {
    fit_points({s}, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FitPoints, BadCloudsAreOneLineErrors) {
  std::vector<Vec3> p, n;
  box_surface({0, 0, 0}, {10, 6, 4}, 1, p, n);
  EXPECT_NE(fit_error({p.begin(), p.begin() + 5}, {n.begin(), n.begin() + 5}).find("too few points"), std::string::npos);
  std::vector<Vec3> bad = p;
  bad[3][1] = std::nan("");
  EXPECT_NE(fit_error(bad, n).find("not finite"), std::string::npos);
  std::vector<Vec3> zero = n;
  zero[4] = {0, 0, 0};
  EXPECT_NE(fit_error(p, zero).find("zero length"), std::string::npos);
  std::vector<Vec3> line, flat, up;
  for (int i = 0; i < 50; ++i) line.push_back({i * 1.0, 2.0 * i, 3.0}), up.push_back({0, 0, 1});
  EXPECT_NE(fit_error(line, up).find("on a line"), std::string::npos);
  for (int i = 0; i < 50; ++i) flat.push_back({i % 7 * 1.0, i / 7 * 1.0, 3.0});
  EXPECT_NE(fit_error(flat, up, ScanKind::All).find("on a plane"), std::string::npos);
  std::vector<Vec3> low = flat;
  for (Vec3& q : low) q[2] = -1;
  EXPECT_NE(fit_error(low, up).find("floor"), std::string::npos);
}

// A scan from above ends at its last row of points, half a spacing inside the edge: the box the
// search leaves there (hull-tight) is widened to the edge, its top and bottom stay, and the
// fitness is not lowered. All around, the walls' points pin every face: nothing moves.
TEST(UntieAgainstPoints, MovesAScannedEdgeHalfASpacingPastTheLastRow) {
  const PointTarget top = box_target(ScanKind::Top);
  const FitnessWeights w;
  Node3D tree = Node3D::leaf(Primitive3D::box(5, 3, 2, 9.5, 5.5, 4));
  FitnessTerms terms = point_fitness(tree, top, w);
  const double before = terms.fitness;
  untie_against_points(tree, terms, top, w, std::chrono::steady_clock::now() + std::chrono::seconds(30));
  const Primitive3D& p = tree.primitive;
  EXPECT_NEAR(p.dims[0], 10, 0.05);
  EXPECT_NEAR(p.dims[1], 6, 0.05);
  EXPECT_NEAR(p.cz + 0.5 * p.dims[2], 4, 1e-6);
  EXPECT_NEAR(p.cz - 0.5 * p.dims[2], 0, 1e-6);
  EXPECT_GE(terms.fitness, before - 1e-12);

  const PointTarget all = box_target(ScanKind::All);
  tree = Node3D::leaf(kBox);
  terms = point_fitness(tree, all, w);
  untie_against_points(tree, terms, all, w, std::chrono::steady_clock::now() + std::chrono::seconds(30));
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(tree.primitive.dims[a], kBox.dims[a], 1e-6);
  EXPECT_NEAR(tree.primitive.cx, kBox.cx, 1e-6);
}

// Two crosses (the point benchmark's kind of part) sampled all around on a jittered grid: the
// level footprints end at the walls (the closing that joins the top's random points would
// otherwise fill the corners between the arms), so each level is its bars.
TEST(HeightLevels, WallsEndTheFootprintsOfAScanAllAround) {
  const Quaternion turn = Quaternion::from_axis_angle(0, 0, 1, 45);
  const std::vector<Primitive3D> bars = {
      Primitive3D::box(20, 20, 4, 40, 8, 8), Primitive3D::box(20, 20, 4, 8, 40, 8),
      Primitive3D::box(20, 20, 6, 32, 6, 12, turn), Primitive3D::box(20, 20, 6, 6, 32, 12, turn)};
  const auto part = [&](double x, double y, double z) {
    for (const Primitive3D& b : bars)
      if (b.contains(x, y, z)) return true;
    return false;
  };
  std::vector<Vec3> pts, nrm;
  std::uint64_t state = 7;
  const auto jitter = [&] {  // a small deterministic generator: the test needs no library's
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5) * 0.3;
  };
  for (const Primitive3D& b : bars) {
    std::vector<Vec3> local, normals;
    box_surface({-b.dims[0] / 2, -b.dims[1] / 2, -b.dims[2] / 2}, {b.dims[0] / 2, b.dims[1] / 2, b.dims[2] / 2}, 0.5,
                local, normals);
    const Mat3 m = b.rotation.matrix();
    for (std::size_t i = 0; i < local.size(); ++i) {
      Vec3 q = local[i], n{};
      for (int a = 0; a < 3; ++a)
        if (std::fabs(normals[i][a]) < 0.5) q[a] += jitter();
      Vec3 p{b.cx, b.cy, b.cz};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) p[r] += m[r][c] * q[c], n[r] += m[r][c] * normals[i][c];
      bool hidden = false;
      for (const Primitive3D& o : bars)
        hidden = hidden || (&o != &b && o.contains(p[0] - 0.01 * n[0], p[1] - 0.01 * n[1], p[2] - 0.01 * n[2]) &&
                            o.contains(p[0] + 0.01 * n[0], p[1] + 0.01 * n[1], p[2] + 0.01 * n[2]));
      if (!hidden && p[2] > 1e-9) pts.push_back(p), nrm.push_back(n);
    }
  }
  const PointTarget t = make_point_target(pts, nrm, ScanKind::All, 0);
  LevelOptions o;
  o.seconds = 4;
  o.threads = 1;
  const std::vector<Node3D> trees = level_trees(t, {}, o, nullptr);
  ASSERT_FALSE(trees.empty());
  EXPECT_GT(volume_iou(trees[0], part, 40, 40), 0.95);
  EXPECT_LE(trees[0].primitive_count(), 8u);  // 2 + 4 before the search prunes the hidden two
}
