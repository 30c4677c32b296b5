// Checks shared by the primitive tests: a primitive's bounds against hand-worked ones.
#pragma once

#include <gtest/gtest.h>

#include "csgfit/model/primitive3d.h"

namespace csgfit::testing {

/// p.bounds() is [lo, hi] to 1e-12 on every axis.
inline void expect_bounds(const Primitive3D& p, const Vec3& lo, const Vec3& hi) {
  const Bounds3 b = p.bounds();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.lo[a], lo[a], 1e-12) << "axis " << a;
    EXPECT_NEAR(b.hi[a], hi[a], 1e-12) << "axis " << a;
  }
}

}  // namespace csgfit::testing
