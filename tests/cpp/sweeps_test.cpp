// find_sweeps: which subtrees are a profile swept along an axis or about one, and whether each
// leaf's section, swept as the Sweep says, is the leaf again (checked point by point against
// the tree itself, on hand-made parts and on random sweeps).
#include "csgfit/model/sweeps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "csgfit/model/primitive2d.h"
#include "random_sweeps.h"
#include "sweep_parts.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

Node3D leaf(const Primitive3D& p) { return Node3D::leaf(p); }

// ---- the sections, read independently of the analysis --------------------------------------

// Whether the profile point (u, v) is inside the leaf's section.
bool section_contains(SweepKind kind, const SweepSection& s, double u, double v) {
  const Primitive3D& p = *s.leaf;
  const double a = s.angle * kPi / 180;
  // In the section's own axes.
  const double du = u - s.x, dv = v - s.y;
  double lu = std::cos(a) * du + std::sin(a) * dv, lv = -std::sin(a) * du + std::cos(a) * dv;
  if (kind == SweepKind::Linear) {
    switch (p.kind) {
      case PrimitiveKind3D::Box:
        return std::fabs(lu) <= p.dims[s.across[0]] / 2 && std::fabs(lv) <= p.dims[s.across[1]] / 2;
      case PrimitiveKind3D::RoundedBox: {
        // The rectangle of the corner centres grown by the corner radius.
        const double qu = std::fabs(lu) - (p.dims[s.across[0]] / 2 - p.corner);
        const double qv = std::fabs(lv) - (p.dims[s.across[1]] / 2 - p.corner);
        return std::hypot(std::max(qu, 0.0), std::max(qv, 0.0)) + std::min(std::max(qu, qv), 0.0) <=
               p.corner;
      }
      case PrimitiveKind3D::Cylinder: {
        if (!p.is_polygonal()) return du * du + dv * dv <= p.dims[0] * p.dims[0];
        const double apothem = p.dims[0] * std::cos(kPi / p.sides);
        for (int i = 0; i < p.sides; ++i) {
          const double n = (2 * i + 1) * kPi / p.sides;
          if (std::cos(n) * lu + std::sin(n) * lv > apothem) return false;
        }
        return true;
      }
      case PrimitiveKind3D::TriangularPrism:
        if (s.flipped) lv = -lv;
        return Primitive::triangle(0, 0, p.dims[0], p.dims[1], 0, p.apex).contains(lu, lv);
      default: ADD_FAILURE() << "no linear section of a " << to_string(p.kind); return false;
    }
  }
  const double h = p.dims[2];
  switch (p.kind) {
    case PrimitiveKind3D::Cylinder: return u <= p.dims[0] && std::fabs(v - s.y) <= h / 2;
    case PrimitiveKind3D::Cone: {
      const double t = (v - (s.y - h / 2)) / h;
      const double low = s.flipped ? p.dims[1] : p.dims[0], high = s.flipped ? p.dims[0] : p.dims[1];
      return t >= 0 && t <= 1 && u <= low + (high - low) * t;
    }
    case PrimitiveKind3D::Torus:
      return (u - p.dims[0]) * (u - p.dims[0]) + (v - s.y) * (v - s.y) <= p.dims[1] * p.dims[1];
    case PrimitiveKind3D::Sphere: return u * u + (v - s.y) * (v - s.y) <= p.dims[0] * p.dims[0];
    default: ADD_FAILURE() << "no revolved section of a " << to_string(p.kind); return false;
  }
}

// The subtree with every leaf replaced by its section, at the profile point (u, v).
bool profile_contains(const Sweep& s, const Node3D& n, double u, double v) {
  if (n.is_leaf()) return section_contains(s.kind, *s.section_of(&n.primitive), u, v);
  bool in = profile_contains(s, n.children[0], u, v);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    const bool c = profile_contains(s, n.children[i], u, v);
    in = n.kind == NodeKind::Union ? in || c : n.kind == NodeKind::Intersection ? in && c : in && !c;
  }
  return in;
}

// Whether the point is inside the sweep as its frame, height and sections say.
bool sweep_contains(const Sweep& s, const Vec3& point) {
  const Mat3 m = s.rotation.matrix();
  Vec3 local{0, 0, 0};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) local[c] += m[r][c] * (point[r] - s.origin[r]);
  if (s.kind == SweepKind::Linear)
    return local[2] >= 0 && local[2] <= s.height && profile_contains(s, *s.root, local[0], local[1]);
  return profile_contains(s, *s.root, std::hypot(local[0], local[1]), local[2]);
}

// Random points in the subtree's bounds (a margin around them): the sweep and the subtree
// agree at each. Returns how many points were inside.
int expect_same_solid(const Sweep& s, std::mt19937_64& rng, int points = 4000) {
  const std::vector<const Primitive3D*> ls = leaves(*s.root);
  Bounds3 b = ls.front()->bounds();
  for (const Primitive3D* p : ls) b = merged(b, p->bounds());
  std::uniform_real_distribution<double> unit(-0.1, 1.1);
  int inside = 0, wrong = 0;
  for (int i = 0; i < points; ++i) {
    Vec3 q;
    for (int c = 0; c < 3; ++c) q[c] = b.lo[c] + unit(rng) * (b.hi[c] - b.lo[c]);
    const bool want = contains(*s.root, q[0], q[1], q[2]);
    inside += want;
    if (sweep_contains(s, q) != want && ++wrong <= 3)
      ADD_FAILURE() << "the sweep and the tree differ at (" << q[0] << ", " << q[1] << ", "
                    << q[2] << "); the tree has it " << (want ? "inside" : "outside") << ": "
                    << structure_string(*s.root);
  }
  return inside;
}

// ---- hand-made parts -----------------------------------------------------------------------

TEST(Sweeps, PlateWithHolesIsOneLinearSweepAcrossItsThickness) {
  const Node3D plate = testing::plate_with_holes();
  const std::vector<Sweep> sweeps = find_sweeps(plate);
  ASSERT_EQ(sweeps.size(), 1u);
  const Sweep& s = sweeps[0];
  EXPECT_EQ(s.kind, SweepKind::Linear);
  EXPECT_EQ(s.root, &plate);
  EXPECT_EQ(s.node, 0u);
  EXPECT_NEAR(s.height, 4, 1e-12);  // the round holes reach beyond the plate: cut to it
  EXPECT_TRUE(s.rotation.is_identity());
  EXPECT_NEAR(s.origin[2], 8, 1e-12);
  ASSERT_EQ(s.sections.size(), 4u);
  EXPECT_NEAR(s.sections[0].x, 16, 1e-12);
  EXPECT_NEAR(s.sections[0].y, 16, 1e-12);
  EXPECT_NEAR(s.sections[0].angle, 0, 1e-9);
  EXPECT_EQ(s.sections[0].across[0], 0);
  EXPECT_EQ(s.sections[0].across[1], 1);
  EXPECT_NEAR(s.sections[2].x, 24, 1e-12);
  EXPECT_NEAR(s.sections[3].angle, 10, 1e-9);  // the hexagon's vertex 0
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(s.sections[i].leaf_index, i);
  std::mt19937_64 rng(1);
  EXPECT_GT(expect_same_solid(s, rng), 100);
}

// A rounded plate minus a hole and a slot is a plate with holes too: its section is the
// rounded rectangle, which the plane sees turned back to its long side along x.
TEST(Sweeps, RoundedPlateWithASlotIsOneLinearSweep) {
  const Node3D plate = testing::rounded_plate_with_slot();
  const std::vector<Sweep> sweeps = find_sweeps(plate);
  ASSERT_EQ(sweeps.size(), 1u);
  const Sweep& s = sweeps[0];
  EXPECT_EQ(s.kind, SweepKind::Linear);
  EXPECT_EQ(s.root, &plate);
  EXPECT_NEAR(s.height, 4, 1e-12);
  EXPECT_TRUE(s.rotation.is_identity());
  EXPECT_NEAR(s.origin[2], 8, 1e-12);
  ASSERT_EQ(s.sections.size(), 3u);
  EXPECT_EQ(s.sections[0].across[0], 1);  // the rounded box's y (26) is the plane's x
  EXPECT_EQ(s.sections[0].across[1], 0);
  EXPECT_NEAR(s.sections[0].angle, 0, 1e-9);
  EXPECT_NEAR(s.sections[2].x, 22, 1e-12);
  EXPECT_NEAR(s.sections[2].angle, 30, 1e-9);
  std::mt19937_64 rng(6);
  EXPECT_GT(expect_same_solid(s, rng), 100);
}

// A rounded box is a prism along its local z only: beside a box of its sizes it is swept along
// z, however thin it is across.
TEST(Sweeps, RoundedBoxIsAPrismAlongItsLocalZOnly) {
  const Node3D pair =
      Node3D::op(NodeKind::Union, {leaf(Primitive3D::rounded_box(0, 0, 0, 10, 4, 10, 1)),
                                   leaf(Primitive3D::box(8, 0, 0, 10, 4, 10))});
  const std::vector<Sweep> sweeps = find_sweeps(pair);
  ASSERT_EQ(sweeps.size(), 1u);
  EXPECT_NEAR(sweeps[0].height, 10, 1e-12);  // not 4 (along y), as two boxes would be
  EXPECT_TRUE(sweeps[0].rotation.is_identity());
  std::mt19937_64 rng(7);
  EXPECT_GT(expect_same_solid(sweeps[0], rng), 100);
  // Lying on its side, it is no prism along the box's z.
  const Quaternion on_its_side = Quaternion::from_euler_deg(90, 0, 0);
  const Node3D lying = Node3D::op(
      NodeKind::Union, {leaf(Primitive3D::rounded_box(0, 0, 0, 10, 10, 4, 1, on_its_side)),
                        leaf(Primitive3D::box(8, 0, 0, 10, 10, 4))});
  EXPECT_TRUE(find_sweeps(lying).empty());
}

// Two boxes of an L, both 14 long in y: the L is the profile, swept along y, drawn upright.
TEST(Sweeps, BracketOfTwoBoxesIsSweptAlongTheirCommonLength) {
  const Node3D bracket = testing::bracket();
  const std::vector<Sweep> sweeps = find_sweeps(bracket);
  ASSERT_EQ(sweeps.size(), 1u);
  const Sweep& s = sweeps[0];
  EXPECT_EQ(s.kind, SweepKind::Linear);
  EXPECT_NEAR(s.height, 14, 1e-9);
  const Mat3 m = s.rotation.matrix();
  EXPECT_NEAR(m[2][1], 1, 1e-12);   // the profile's y is the model's z
  EXPECT_NEAR(m[1][2], -1, 1e-12);  // swept down y, from y = 23
  EXPECT_NEAR(s.origin[1], 23, 1e-9);
  EXPECT_NEAR(s.sections[1].x, 6, 1e-9);
  EXPECT_NEAR(s.sections[1].y, 15, 1e-9);
  std::mt19937_64 rng(2);
  EXPECT_GT(expect_same_solid(s, rng), 100);
}

// A bush with a torus round it is turned; so is the tilted one.
TEST(Sweeps, TurnedPartIsOneRevolution) {
  const Node3D part = testing::turned_part();
  const std::vector<Sweep> upright = find_sweeps(part);
  ASSERT_EQ(upright.size(), 1u);
  EXPECT_EQ(upright[0].kind, SweepKind::Revolution);
  EXPECT_NEAR(upright[0].origin[0], 16, 1e-12);
  EXPECT_NEAR(upright[0].origin[2], 0, 1e-12);
  EXPECT_NEAR(upright[0].sections[2].y, 16, 1e-12);
  Node3D tilted = part;
  rotate_tree(tilted, Quaternion::from_euler_deg(20, -35, 0));
  leaves(tilted)[2]->rotation = leaves(tilted)[2]->rotation * Quaternion::from_euler_deg(180, 0, 0);
  const std::vector<Sweep> sweeps = find_sweeps(tilted);
  ASSERT_EQ(sweeps.size(), 1u);
  EXPECT_EQ(sweeps[0].kind, SweepKind::Revolution);
  EXPECT_EQ(sweeps[0].root, &tilted);
  std::mt19937_64 rng(3);
  EXPECT_GT(expect_same_solid(sweeps[0], rng), 100);
  // Without the torus it is a tube: a linear sweep of a ring, which a designer draws so.
  const std::vector<Sweep> tube = find_sweeps(tilted.children[0]);
  ASSERT_EQ(tube.size(), 1u);
  EXPECT_EQ(tube[0].kind, SweepKind::Linear);
  EXPECT_NEAR(tube[0].height, 12, 1e-9);
}

// A stepped shaft: coaxial cylinders of different lengths and a cone, one of them upside down.
TEST(Sweeps, SteppedShaftWithAConeIsARevolution) {
  const Node3D shaft = Node3D::op(
      NodeKind::Union,
      {leaf(Primitive3D::cylinder(0, 0, 5, 4, 10)), leaf(Primitive3D::cylinder(0, 0, 13, 2, 6)),
       leaf(Primitive3D::cone(0, 0, -2, 4, 1, 4, Quaternion::from_euler_deg(180, 0, 0))),
       leaf(Primitive3D::sphere(0, 0, 16, 2))});
  const std::vector<Sweep> sweeps = find_sweeps(shaft);
  ASSERT_EQ(sweeps.size(), 1u);
  const Sweep& s = sweeps[0];
  EXPECT_EQ(s.kind, SweepKind::Revolution);
  EXPECT_TRUE(s.rotation.is_identity(1e-12));
  EXPECT_TRUE(s.sections[2].flipped);
  EXPECT_NEAR(s.sections[1].y, 13, 1e-12);
  std::mt19937_64 rng(4);
  EXPECT_GT(expect_same_solid(s, rng), 100);
}

TEST(Sweeps, BoxesOfDifferentHeightsAreNoSweep) {
  // Side by side, but of different heights; along x and y they do not span each other either.
  EXPECT_TRUE(find_sweeps(testing::steps()).empty());
  // A blind hole is no through-hole: the plate's section is not the same all through.
  const Node3D blind = Node3D::op(NodeKind::Difference, {leaf(Primitive3D::box(0, 0, 2.5, 20, 20, 5)),
                                                         leaf(Primitive3D::cylinder(0, 0, 4, 2, 3))});
  EXPECT_TRUE(find_sweeps(blind).empty());
  // One leaf is a primitive, not a sweep.
  EXPECT_TRUE(find_sweeps(leaf(Primitive3D::box(0, 0, 0, 1, 2, 3))).empty());
}

// The largest sweeps inside a tree that is none: the plate (node 1) and the turned knob
// (node 7), each once; nothing inside either is reported.
TEST(Sweeps, LargestSubtreesAreFoundOnce) {
  const Node3D knob = Node3D::op(NodeKind::Union, {leaf(Primitive3D::cylinder(16, 16, 15, 3, 6)),
                                                   leaf(Primitive3D::sphere(16, 16, 18, 3))});
  const Node3D part = Node3D::op(
      NodeKind::Union,
      {testing::plate_with_holes(), leaf(Primitive3D::ellipsoid(0, 0, 0, 1, 2, 3)), knob});
  const std::vector<Sweep> sweeps = find_sweeps(part);
  ASSERT_EQ(sweeps.size(), 2u);
  EXPECT_EQ(sweeps[0].node, 1u);
  EXPECT_EQ(sweeps[0].kind, SweepKind::Linear);
  EXPECT_EQ(sweeps[1].node, 7u);
  EXPECT_EQ(sweeps[1].kind, SweepKind::Revolution);
  EXPECT_EQ(sweeps[1].sections[0].leaf_index, 5u);
  EXPECT_EQ(sweeps[1].sections[1].leaf_index, 6u);
}

TEST(Sweeps, AnIntersectedLeafMayReachBeyondTheExtent) {
  // A rounded-off bar: a 4 mm thick box cut by a long cylinder across it, both along y.
  const Quaternion along_y = Quaternion::from_euler_deg(90, 0, 0);
  const Node3D bar = Node3D::op(NodeKind::Intersection,
                                {leaf(Primitive3D::box(0, 0, 0, 10, 4, 6)),
                                 leaf(Primitive3D::cylinder(0, 0, 0, 5.5, 30, along_y))});
  const std::vector<Sweep> sweeps = find_sweeps(bar);
  ASSERT_EQ(sweeps.size(), 1u);
  EXPECT_NEAR(sweeps[0].height, 4, 1e-9);
  std::mt19937_64 rng(5);
  EXPECT_GT(expect_same_solid(sweeps[0], rng), 100);
}

TEST(Sweeps, RandomSweepsAreFoundWholeAndDrawTheirTree) {
  const std::uint64_t seed = testing::test_seed();
  SCOPED_TRACE("CSGFIT_TEST_SEED=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int t = 0; t < 120; ++t) {
    testing::SweepRegion region;
    region.frame = testing::random_sweep_frame(rng);
    const bool linear = t % 2 == 0;
    const Node3D tree =
        linear ? testing::random_linear_tree(rng, region) : testing::random_revolution_tree(rng, region);
    const std::vector<Sweep> sweeps = find_sweeps(tree);
    ASSERT_EQ(sweeps.size(), 1u) << structure_string(tree);
    EXPECT_EQ(sweeps[0].root, &tree);
    if (!linear) EXPECT_EQ(sweeps[0].kind, SweepKind::Revolution);
    expect_same_solid(sweeps[0], rng, 1500);
  }
}

}  // namespace
}  // namespace csgfit
