// VoxelGrid: bit layout, spans, padding, whole-grid operations and counts.
#include "csgfit/model/voxel_grid.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

using namespace csgfit;

TEST(VoxelGrid, ConstructionAndPlacement) {
  VoxelGrid g(70, 3, 2, -1.0, 2.0, 0.5, 0.25);
  EXPECT_EQ(g.words_per_row(), 2);
  EXPECT_EQ(g.word_count(), 2u * 3 * 2);
  EXPECT_EQ(g.count(), 0u);
  EXPECT_FALSE(g.empty());
  EXPECT_DOUBLE_EQ(g.center_x(0), -1.0 + 0.125);
  EXPECT_DOUBLE_EQ(g.center_y(2), 2.0 + 2.5 * 0.25);
  EXPECT_DOUBLE_EQ(g.center_z(1), 0.5 + 1.5 * 0.25);
  EXPECT_TRUE(VoxelGrid(0, 5, 5).empty());
  EXPECT_THROW(VoxelGrid(-1, 2, 2), std::invalid_argument);
  EXPECT_THROW(VoxelGrid(2, 2, 2, 0, 0, 0, 0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid(2, 2, 2, 0, 0, 0, -1), std::invalid_argument);
}

TEST(VoxelGrid, SetGetAndRowLayout) {
  VoxelGrid g(130, 4, 3);
  g.set(129, 3, 2);
  g.set(0, 0, 0);
  g.set(64, 1, 1);
  EXPECT_TRUE(g.get(129, 3, 2));
  EXPECT_TRUE(g.get(0, 0, 0));
  EXPECT_TRUE(g.get(64, 1, 1));
  EXPECT_FALSE(g.get(63, 1, 1));
  EXPECT_EQ(g.count(), 3u);
  // Rows are ordered by j then k, x fastest within a row.
  EXPECT_EQ(g.row_words(1, 1) - g.data(), (1 * 4 + 1) * 3);
  EXPECT_EQ(g.row_words(1, 1)[1], 1u);
  g.set(64, 1, 1, false);
  EXPECT_FALSE(g.get(64, 1, 1));
  EXPECT_EQ(g.count(), 2u);
}

TEST(VoxelGrid, SpansMatchSingleBits) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    const int nx = 1 + static_cast<int>(rng() % 200);
    VoxelGrid a(nx, 2, 2), b(nx, 2, 2);
    const int i0 = static_cast<int>(rng() % (nx + 1));
    const int i1 = i0 + static_cast<int>(rng() % (nx - i0 + 1));
    a.set_span(1, 1, i0, i1);
    for (int i = i0; i < i1; ++i) b.set(i, 1, 1);
    ASSERT_EQ(a, b) << nx << " " << i0 << " " << i1;
    ASSERT_EQ(a.count(), static_cast<std::size_t>(i1 - i0));
  }
}

TEST(VoxelGrid, FillKeepsPaddingZero) {
  VoxelGrid g(70, 3, 5);
  g.fill();
  EXPECT_EQ(g.count(), 70u * 3 * 5);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(g.row_words(j, k)[1] >> 6, 0u);
  g.clear();
  EXPECT_EQ(g.count(), 0u);
  VoxelGrid full(128, 2, 2);
  full.fill();
  EXPECT_EQ(full.count(), 512u);
}

TEST(VoxelGrid, BooleanOperationsAndCounts) {
  std::mt19937 rng(7);
  VoxelGrid a(90, 7, 6), b(90, 7, 6);
  std::size_t na = 0, nb = 0, nab = 0;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 90; ++i) {
        const bool va = rng() % 3 == 0, vb = rng() % 2 == 0;
        if (va) a.set(i, j, k), ++na;
        if (vb) b.set(i, j, k), ++nb;
        if (va && vb) ++nab;
      }
  EXPECT_EQ(count_and(a, b), nab);
  EXPECT_EQ(count_and_not(a, b), na - nab);
  EXPECT_EQ(count_xor(a, b), na + nb - 2 * nab);
  EXPECT_DOUBLE_EQ(iou(a, b), static_cast<double>(nab) / static_cast<double>(na + nb - nab));
  VoxelGrid u = a;
  u |= b;
  EXPECT_EQ(u.count(), na + nb - nab);
  VoxelGrid n = a;
  n &= b;
  EXPECT_EQ(n.count(), nab);
  VoxelGrid d = a;
  d.subtract(b);
  EXPECT_EQ(d.count(), na - nab);
  EXPECT_DOUBLE_EQ(iou(VoxelGrid(4, 4, 4), VoxelGrid(4, 4, 4)), 1.0);
  EXPECT_THROW(a |= VoxelGrid(90, 7, 5), std::invalid_argument);
  EXPECT_THROW(count_xor(a, VoxelGrid(91, 7, 6)), std::invalid_argument);
}

TEST(VoxelGrid, EqualityIncludesPlacement) {
  VoxelGrid a(8, 8, 8), b(8, 8, 8, 0, 0, 0, 2.0), c(8, 8, 8);
  EXPECT_EQ(a, c);
  EXPECT_NE(a, b);
  c.set(1, 2, 3);
  EXPECT_NE(a, c);
}
