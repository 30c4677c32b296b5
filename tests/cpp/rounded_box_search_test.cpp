// The rounded box in the stages around the model: the local optimiser's corner move, the voxel
// search's change of kind and its kinds, seed 004's terminals and curvature, the untie and snap
// steps, the morph's interpolation, seed 002's report, pockets and hidden faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_features.h"
#include "csgfit/model/interpolate.h"
#include "csgfit/optimise/snap3d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/search/hidden_extents.h"
#include "csgfit/seed/evidence_pockets.h"
#include "csgfit/seed/precedence_graph.h"
#include "pipeline/problems.h"
#include "range_graphs.h"
#include "refine/moves3d.h"
#include "search/gp_operators.h"
#include "search/operators3d.h"
#include "search/untie_points.h"

namespace csgfit {
namespace {

using Param = Moves3D::Param;

int count(const Param* params, int n, Param which) {
  return static_cast<int>(std::count(params, params + n, which));
}

TEST(RoundedBoxSearch, TheLocalOptimiserMovesTheCornerOntoTheTargets) {
  const Primitive3D truth = Primitive3D::rounded_box(16, 16, 8, 24, 16, 8, 6);
  Param params[Moves3D::kMaxParams];
  const int n = Moves3D{1.0}.params_of(truth, LocalOptOptions{}, params);
  EXPECT_EQ(count(params, n, Param::Corner), 1);
  EXPECT_EQ(n, 3 + 3 + 1 + 3) << "centre, sizes, corner, turns";
  EXPECT_EQ(count(params, Moves3D{1.0}.params_of(Primitive3D::box(0, 0, 0, 1, 1, 1), LocalOptOptions{},
                                                 params),
                  Param::Corner),
            0);
  // Faces one at a time (the range refinement's moves): six faces, the corner, the turns.
  Moves3D faces{1.0};
  faces.box_faces = true;
  EXPECT_EQ(faces.params_of(truth, LocalOptOptions{}, params), Moves3D::kMaxParams);

  VoxelGrid target(32, 32, 16, 0, 0, 0, 1.0);
  rasterize(truth, target);
  Primitive3D start = truth;
  start.corner = 2;
  Node3D tree = Node3D::leaf(start);
  TreeEvaluator3D ev(target, tree);
  const std::size_t before = ev.mismatch().total();
  optimize_leaves(ev, LocalOptOptions{});
  EXPECT_LT(ev.mismatch().total(), before / 4);
  EXPECT_EQ(ev.leaf(0).kind, PrimitiveKind3D::RoundedBox);
  EXPECT_NEAR(ev.leaf(0).corner, 6, 0.75);
}

TEST(RoundedBoxSearch, AChangeOfKindKeepsTheExtentsAndRoundsHalfway) {
  const Quaternion q = Quaternion::from_axis_angle(0, 0, 1, 30);
  const Primitive3D box = Primitive3D::box(1, 2, 3, 20, 10, 4, q);
  const Primitive3D rounded = Operators3D::rekinded(box, PrimitiveKind3D::RoundedBox);
  EXPECT_EQ(rounded.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_EQ(rounded.dims, box.dims);
  EXPECT_EQ(rounded.rotation, box.rotation);
  EXPECT_DOUBLE_EQ(rounded.corner, 2.5) << "half of the stadium's 5";
  // And back: a rounded box's extents are its sizes, as a box's.
  const Primitive3D cyl = Operators3D::rekinded(rounded, PrimitiveKind3D::Cylinder);
  EXPECT_DOUBLE_EQ(cyl.dims[0], 7.5);
  EXPECT_DOUBLE_EQ(cyl.dims[2], 4);
}

TEST(RoundedBoxSearch, TheVoxelSearchDrawsItOnlyWhenNamed) {
  VoxelGrid target(16, 16, 16, 0, 0, 0, 1.0);
  rasterize(Primitive3D::box(8, 8, 8, 8, 8, 8), target);
  FitOptions3D options;
  const auto start = std::chrono::steady_clock::now();
  options.primitives = PrimitiveSet3D::parse("box,rounded_box");
  const Problem3D named = make_problem3d(target, options, start, nullptr);
  ASSERT_EQ(named.kinds, (std::vector<PrimitiveKind3D>{PrimitiveKind3D::Box, PrimitiveKind3D::RoundedBox}));
  options.primitives = PrimitiveSet3D::all();
  const Problem3D all = make_problem3d(target, options, start, nullptr);
  EXPECT_EQ(std::count(all.kinds.begin(), all.kinds.end(), PrimitiveKind3D::RoundedBox), 0);
  // MOD among a box and a rounded box turns the one into the other.
  Operators3D ops(named, 5);
  EXPECT_EQ(ops.changed_kind(Primitive3D::box(8, 8, 8, 8, 6, 4), false).kind,
            PrimitiveKind3D::RoundedBox);
}

// A box sampled all around, for seed 004's operators.
PointTarget sampled(const Primitive3D& solid) {
  std::vector<Vec3> points, normals;
  const Bounds3 b = solid.bounds();
  for (double x = b.lo[0]; x <= b.hi[0]; x += 0.5)
    for (double y = b.lo[1]; y <= b.hi[1]; y += 0.5)
      for (double z = b.lo[2]; z <= b.hi[2]; z += 0.5)
        if (std::fabs(solid.signed_distance(x, y, z)) < 0.25) {
          points.push_back({x, y, z});
          normals.push_back(solid.normal_at(x, y, z));
        }
  return make_point_target(points, normals, ScanKind::All, 0);
}

TEST(RoundedBoxSearch, SeedFoursTerminalsAreRoundedBoxesWhoseCornersMutate) {
  const Primitive3D truth = Primitive3D::rounded_box(5, 3, 2, 10, 6, 4, 1);
  const PointTarget t = sampled(truth);
  const std::vector<std::size_t> subset;
  const gp::Context c{&t, &subset, PrimitiveSet3D::parse("rounded_box"), nullptr, 0.05};
  rnd::Rng rng(11);
  GpIndividual g{Node3D::leaf(Primitive3D::box(5, 3, 2, 10, 6, 4)), {0.05}, 0};
  gp::replace_terminal(g, c, rng);
  ASSERT_EQ(leaves(g.tree).size(), 1u);
  const Primitive3D made = *leaves(g.tree)[0];
  EXPECT_EQ(made.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_NEAR(made.corner, std::min(made.dims[0], made.dims[1]) / 4, 1e-12);
  // The corner is one of the mutated parameters.
  g = GpIndividual{Node3D::leaf(truth), {0.05}, 0};
  int changed = 0;
  for (int i = 0; i < 20; ++i) {
    const double before = leaves(g.tree)[0]->corner;
    gp::mutate_terminals(g, c, rng);
    const Primitive3D& p = *leaves(g.tree)[0];
    changed += p.corner != before && p.corner < std::min(p.dims[0], p.dims[1]) / 2;
  }
  EXPECT_GE(changed, 8);
}

TEST(RoundedBoxSearch, ItsArcsAreConvexAndItsFlatsFlat) {
  const Node3D tree = Node3D::leaf(Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3));
  const double d = 3 / std::sqrt(2.0);
  EXPECT_EQ(tree_curvature(tree, {7 + d, 2 + d, 0}), CurvatureType::Convex);
  EXPECT_EQ(tree_curvature(tree, {10, 0, 0}), CurvatureType::Flat);
  EXPECT_EQ(tree_curvature(tree, {0, 5, 1}), CurvatureType::Flat);
  EXPECT_EQ(tree_curvature(tree, {7 + 0.5 * d, 2 + 0.5 * d, 2}), CurvatureType::Flat) << "the top";
}

TEST(RoundedBoxSearch, UntieMovesItsScannedEdgesHalfASpacingPastTheLastRows) {
  // A scan from above of a plate with small corners: its edges are half a spacing past the
  // last rows, where the fit leaves them.
  const Primitive3D truth = Primitive3D::rounded_box(5, 3, 2, 10, 6, 4, 0.3);
  std::vector<Vec3> points, normals;
  for (double x = 0.25; x < 10; x += 0.5)
    for (double y = 0.25; y < 6; y += 0.5)
      if (truth.contains(x, y, 3.9)) points.push_back({x, y, 4}), normals.push_back({0, 0, 1});
  const PointTarget top = make_point_target(points, normals, ScanKind::Top, 0);
  const FitnessWeights w;
  Node3D tree = Node3D::leaf(Primitive3D::rounded_box(5, 3, 2, 9.5, 5.5, 4, 0.3));
  FitnessTerms terms = point_fitness(tree, top, w);
  const double before = terms.fitness;
  untie_against_points(tree, terms, top, w, std::chrono::steady_clock::now() + std::chrono::seconds(30));
  const Primitive3D& p = tree.primitive;
  EXPECT_EQ(p.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_NEAR(p.dims[0], 10, 0.05);
  EXPECT_NEAR(p.dims[1], 6, 0.05);
  EXPECT_NEAR(p.cz + 0.5 * p.dims[2], 4, 1e-6);
  EXPECT_NEAR(p.cz - 0.5 * p.dims[2], 0, 1e-6);
  EXPECT_GE(terms.fitness, before - 1e-12);
}

TEST(RoundedBoxSearch, ItsFlatFacesSnapToTheInputsPlanes) {
  const VoxelGrid frame(30, 20, 16, 0, 0, 0, 1.0);
  VoxelGrid target = frame;
  const Primitive3D truth = Primitive3D::rounded_box(14, 10, 6.15, 24, 10, 8.3, 3);
  rasterize(truth, target);
  // The planes of its flats: those of the box it rounds.
  TriangleMesh mesh;
  const double lo[3] = {2, 5, 2}, hi[3] = {26, 15, 10.3};
  for (int v = 0; v < 8; ++v)
    mesh.vertices.push_back({(v & 1) ? hi[0] : lo[0], (v & 2) ? hi[1] : lo[1], (v & 4) ? hi[2] : lo[2]});
  for (const auto& t : {std::array<int, 3>{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}})
    mesh.triangles.push_back(t);
  Node3D tree = Node3D::leaf(Primitive3D::rounded_box(14.1, 10, 6.2, 24.1, 10.2, 8.3, 3));
  TreeEvaluator3D ev(target, tree);
  EXPECT_GE(snap_to_planes(ev, axis_planes(mesh, 1e-6, 1), 0.4, 0), 3u);
  const Primitive3D& p = ev.leaf(0);
  EXPECT_EQ(p.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_NEAR(p.cx - p.dims[0] / 2, 2, 1e-12);
  EXPECT_NEAR(p.cx + p.dims[0] / 2, 26, 1e-12);
  EXPECT_NEAR(p.cy - p.dims[1] / 2, 5, 1e-12);
  EXPECT_NEAR(p.cy + p.dims[1] / 2, 15, 1e-12);
  EXPECT_NEAR(p.cz + p.dims[2] / 2, 10.3, 1e-12);
}

TEST(RoundedBoxSearch, AMorphMixesTheCorners) {
  const Primitive3D a = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 1);
  const Primitive3D b = Primitive3D::rounded_box(2, 0, 0, 20, 12, 4, 5);
  const Primitive3D half = interpolate(a, b, 0.5);
  EXPECT_EQ(half.kind, PrimitiveKind3D::RoundedBox);
  EXPECT_DOUBLE_EQ(half.corner, 3);
  EXPECT_DOUBLE_EQ(half.dims[1], 11);
}

TEST(RoundedBoxSearch, SeedTwosReportGivesItsAxesLengthsAndCorner) {
  const std::string report =
      precedence_report(testing::graph_of({testing::signed_node(Primitive3D::rounded_box(1, 2, 3, 8, 6, 3, 1.5), true)}));
  EXPECT_NE(report.find("ROUNDED_BOX"), std::string::npos) << report;
  EXPECT_NE(report.find("length: 8.000000"), std::string::npos) << report;
  EXPECT_NE(report.find("corner radius: 1.500000"), std::string::npos) << report;
}

TEST(RoundedBoxSearch, APocketInARoundedBlockReachesThroughTheFacesItMeets) {
  // A slot down the middle of the rounded block's +y side.
  const Primitive3D block = Primitive3D::rounded_box(0, 0, 0, 8, 6, 3, 1);
  const Primitive3D slot = Primitive3D::box(0, 3, 0, 2, 2, 4);
  const RangeEvidence evidence =
      testing::evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(block), Node3D::leaf(slot)}));
  const std::vector<SignedPrimitive> cuts =
      pocket_proposals(testing::graph_of({testing::signed_node(block, true)}), evidence, 0.3);
  ASSERT_FALSE(cuts.empty());
  EXPECT_TRUE(cuts[0].primitive.contains(0, 2.5, 0)) << "the slot's middle";
  EXPECT_TRUE(cuts[0].primitive.contains(0, 3.05, 1.45)) << "through the side and the top";
  EXPECT_FALSE(cuts[0].primitive.contains(0, 1, 0)) << "the block's material stays";
}

TEST(RoundedBoxSearch, AHiddenUndersideMeetsARoundedBarsBottom) {
  // A rounded bar along the plate's +y edge, its bottom at z = -0.75.
  const Primitive3D bar = Primitive3D::rounded_box(0, 3, 0, 8, 1.5, 1.5, 0.5);
  const RangeEvidence evidence =
      testing::evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(testing::kPlate), Node3D::leaf(bar)}));
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(
      testing::graph_of({testing::signed_node(thin, true), testing::signed_node(bar, true)}), evidence);
  const Primitive3D& plate = g.nodes[0].primitive;
  EXPECT_NEAR(plate.cz - plate.dims[2] / 2, -0.75, 1e-9) << "down to the bar's bottom";
  EXPECT_NEAR(plate.cz + plate.dims[2] / 2, 0.75, 1e-9) << "the top stays";
}

}  // namespace
}  // namespace csgfit
