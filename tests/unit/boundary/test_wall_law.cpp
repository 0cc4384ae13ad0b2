// The rigid-wall law (mpm/wall_law.hpp) on single node velocities, against what a rigid
// wall does by definition: a stuck node moves with the wall; in contact the velocity
// relative to the wall loses its normal part (all of it, or only the approach when the
// wall is separable) and, with Coulomb friction, mu |v_n| of its tangential part, not past
// zero (Bardenhagen, Brackbill & Sulsky 2000).
#include <gtest/gtest.h>

#include <cmath>

#include "scree/mpm/wall_law.hpp"

namespace scree {
namespace {

const Real kX[3] = {0.3, 0.2, 0.0};

/// A floor (normal +y) in contact mode: frictionless unless mu is given.
Wall floor_contact(Real mu = 0, int separable = 0) {
  Wall w;
  w.mode = Wall::Mode::contact;
  w.normal[1] = 1;
  w.mu = mu;
  w.separable = separable;
  return w;
}

TEST(WallLaw, AStuckNodeMovesWithTheWallTranslatingAndRotating) {
  Wall w;  // stick
  w.velocity[0] = 0.5;
  w.velocity[1] = -0.1;
  Real v[2] = {3, 4};
  w.apply<2>(v, kX, 0);
  EXPECT_EQ(v[0], 0.5);
  EXPECT_EQ(v[1], -0.1);
  w.rotating = 1;
  w.omega[2] = 2;  // v_w = velocity + omega x (x - c)
  w.centre[0] = 0.1;
  w.apply<2>(v, kX, 0);
  EXPECT_DOUBLE_EQ(v[0], 0.5 - 2 * 0.2);
  EXPECT_DOUBLE_EQ(v[1], -0.1 + 2 * (0.3 - 0.1));
}

TEST(WallLaw, FrictionlessContactRemovesTheNormalVelocityRelativeToAMovingWall) {
  Wall w = floor_contact();
  w.velocity[1] = 0.2;  // rising at 0.2 m/s
  w.velocity[0] = 1.0;  // and sliding: a frictionless wall carries nothing along
  Real v[2] = {0.7, -0.5};
  w.apply<2>(v, kX, 0);
  EXPECT_DOUBLE_EQ(v[0], 0.7);
  EXPECT_DOUBLE_EQ(v[1], 0.2) << "the node follows the floor's normal motion";
}

TEST(WallLaw, SeparableContactLetsTheMaterialLeave) {
  const Wall w = floor_contact(0, 1);
  Real up[2] = {0.3, 0.4};
  w.apply<2>(up, kX, 0);
  EXPECT_EQ(up[1], 0.4) << "moving away: free";
  Real down[2] = {0.3, -0.4};
  w.apply<2>(down, kX, 0);
  EXPECT_EQ(down[1], 0) << "approaching: stopped";
}

TEST(WallLaw, CoulombFrictionTakesMuTimesTheNormalSpeedOffTheSlidingSpeed) {
  Wall w = floor_contact(0.5);
  Real v[2] = {1.0, -0.4};  // sliding at 1 m/s, pressed at 0.4 m/s: slides at 1 - 0.5 * 0.4
  w.apply<2>(v, kX, 0);
  EXPECT_DOUBLE_EQ(v[0], 0.8);
  EXPECT_EQ(v[1], 0);
  Real slow[2] = {0.1, -0.4};  // friction stops it, and never reverses it
  w.apply<2>(slow, kX, 0);
  EXPECT_EQ(slow[0], 0);
  // Against a wall sliding at 1 m/s the same holds for the relative velocity.
  w.velocity[0] = 1.0;
  Real rel[2] = {2.0, -0.4};
  w.apply<2>(rel, kX, 0);
  EXPECT_DOUBLE_EQ(rel[0], 1.8);
}

TEST(WallLaw, AWallActsOnlyInItsTimeWindow) {
  Wall w;  // stick, at rest
  w.t_start = 0.1;
  w.t_end = 0.2;
  Real v[2] = {1, 1};
  w.apply<2>(v, kX, 0.05);
  EXPECT_EQ(v[0], 1);
  w.apply<2>(v, kX, 0.2);
  EXPECT_EQ(v[0], 1) << "t_end is excluded: a gate removed at 0.2 s";
  w.apply<2>(v, kX, 0.15);
  EXPECT_EQ(v[0], 0);
}

TEST(WallLaw, MasksApplyTheirWallsInIndexOrder) {
  Wall table[2];
  table[0].velocity[0] = 1;  // stick to 1 m/s ...
  table[1].mode = Wall::Mode::contact;
  table[1].normal[0] = 1;  // ... then a frictionless wall normal to x stops it
  Real v[2] = {5, 5};
  apply_walls<2>(table, WallMask(3), v, kX, 0);
  EXPECT_EQ(v[0], 0);
  EXPECT_EQ(v[1], 0);
}

}  // namespace
}  // namespace scree
