// Time-of-impact solvers: cases a person can check by hand, and the rounding conventions.
#include "time_of_impact.hpp"

#include <gtest/gtest.h>

#include <cmath>

using billiard::kNever;
using billiard::Vector;

namespace {
const Vector kNoGravity = Vector::Zero();
}

TEST(StableQuadratic, KeepsTheSmallRootWhenTheTextbookFormulaCancels) {
  // t^2 - 1e8 t + 1 = 0: roots 1e-8 and 1e8. The textbook formula gives the small one as
  // (1e8 - sqrt(1e16 - 4)) / 2 = 0 in double precision; the stable form keeps it to full
  // precision (relative error 1e-15 is rounding).
  const billiard::QuadraticRoots r = billiard::solve_quadratic(1, -1e8, 1);
  ASSERT_EQ(r.count, 2);
  EXPECT_NEAR(r.lo, 1e-8, 1e-8 * 1e-15);
  EXPECT_NEAR(r.hi, 1e8, 1e8 * 1e-15);
}

TEST(StableQuadratic, LinearAndNoRealRoots) {
  EXPECT_EQ(billiard::solve_quadratic(0, 2, -4).count, 1);
  EXPECT_EQ(billiard::solve_quadratic(0, 2, -4).lo, 2);
  EXPECT_EQ(billiard::solve_quadratic(1, 0, 1).count, 0);
}

TEST(DiscDisc, HeadOnCollisionAtTimeFour) {
  // Discs of radius 1 at x = 0 and x = 10 approaching at relative speed 2: the gap of 8
  // closes at t = 4 (exact in binary floating point).
  EXPECT_EQ(billiard::disc_disc_time(Vector(0, 0) - Vector(10, 0), Vector(1, 0) - Vector(-1, 0), 2.0), 4.0);
}

TEST(DiscDisc, SeparatingGrazingAndMissingPairsNeverCollide) {
  EXPECT_EQ(billiard::disc_disc_time(Vector(-3, 0), Vector(-1, 0), 2.0), kNever);   // flying apart
  EXPECT_EQ(billiard::disc_disc_time(Vector(-3, 2), Vector(0, -0.0), 2.0), kNever);  // at rest
  EXPECT_EQ(billiard::disc_disc_time(Vector(-3, 2), Vector(0, 1), 2.0), kNever);     // side by side, b = 0
  // Passing at distance 2.5 > 2: a miss.
  EXPECT_EQ(billiard::disc_disc_time(Vector(-5, 2.5), Vector(1, 0), 2.0), kNever);
}

TEST(DiscDisc, JustCollidedPairIsRejectedWithoutEpsilon) {
  // Touching (c ~ 0 up to rounding) and separating (b > 0): no second collision.
  const Vector dr(2.0 * std::cos(0.3), 2.0 * std::sin(0.3));
  EXPECT_EQ(billiard::disc_disc_time(dr, Vector(0.1, 0.05), 2.0), kNever);
}

TEST(DiscDisc, RoundingOverlapWhileApproachingCollidesNow) {
  EXPECT_EQ(billiard::disc_disc_time(Vector(2.0 - 1e-15, 0), Vector(-1, 0), 2.0), 0.0);
}

TEST(Circle, DiscAtCentreHitsWallAtReachOverSpeed) {
  // R - a = 9 at speed 2: t = 4.5.
  EXPECT_DOUBLE_EQ(billiard::disc_in_circle_time(Vector(0, 0), Vector(2, 0), kNoGravity, 9.0), 4.5);
  EXPECT_EQ(billiard::disc_in_circle_time(Vector(1, 1), Vector(0, 0), kNoGravity, 9.0), kNever);
}

TEST(Circle, DiscDroppedFromTheCentreUnderGravity) {
  // From rest at the centre, falling with g = 9.81 to reach 4: t = sqrt(2 * 4 / 9.81)
  // (the quartic solver is bisected to rounding: 1e-12 relative).
  const double t = billiard::disc_in_circle_time(Vector(0, 0), Vector(0, 0), Vector(0, -9.81), 4.0);
  EXPECT_NEAR(t, std::sqrt(8 / 9.81), 1e-12);
}

TEST(Circle, DiscDroppedFromRestAtTheCentreReachesTheRimForAnyGAndReach) {
  // The time bound of the quartic search is exact for this drop (|g| t^2 / 2 = reach), so
  // rounding at the bound must not lose the crossing: t = sqrt(2 reach / |g|) for every pair.
  for (const double g : {1.0, 2.0, 9.81, 0.37, 1e-3, 250.0}) {
    for (const double reach : {9.0, 9.0 + 1e-10, 4.0, 1.0, 0.3, 123.456}) {
      const double t = billiard::disc_in_circle_time(Vector(0, 0), Vector(0, 0), Vector(0, -g), reach);
      EXPECT_NEAR(t, std::sqrt(2 * reach / g), 1e-12 * std::sqrt(2 * reach / g)) << "g = " << g << ", reach = " << reach;
    }
  }
}

TEST(Circle, ThrownSidewaysUnderGravityLandsOnTheRim) {
  // Any disc under gravity reaches the rim; the answer must put it at distance reach.
  const Vector r(1, 2), v(3, 1), g(0.5, -2);
  const double t = billiard::disc_in_circle_time(r, v, g, 6.0);
  ASSERT_LT(t, kNever);
  EXPECT_NEAR((r + v * t + 0.5 * g * t * t).norm(), 6.0, 1e-12);
}

TEST(Circle, RoundingOutsideMovingOutBouncesNow) {
  EXPECT_EQ(billiard::disc_in_circle_time(Vector(9.0 + 1e-15, 0), Vector(1, 0), kNoGravity, 9.0), 0.0);
  EXPECT_EQ(billiard::disc_in_circle_time(Vector(9.0 + 1e-15, 0), Vector(1, 0), Vector(0, -1), 9.0), 0.0);
}

TEST(Segment, DiscFallsOntoAFloor) {
  // Floor from (-10, 0) to (10, 0); disc of radius 1 at height 3, falling at speed 1: the gap
  // of 2 closes at t = 2. Under gravity g = 2 from rest: 2 = t^2, t = sqrt(2).
  EXPECT_DOUBLE_EQ(billiard::disc_segment_time(Vector(0, 3), Vector(0, -1), kNoGravity, Vector(-10, 0), Vector(10, 0), 1.0), 2.0);
  EXPECT_NEAR(billiard::disc_segment_time(Vector(0, 3), Vector(0, 0), Vector(0, -2), Vector(-10, 0), Vector(10, 0), 1.0),
              std::sqrt(2.0), 1e-15);
  // From below the segment (two-sided) and missing it past its end.
  EXPECT_DOUBLE_EQ(billiard::disc_segment_time(Vector(0, -3), Vector(0, 1), kNoGravity, Vector(-10, 0), Vector(10, 0), 1.0), 2.0);
  EXPECT_EQ(billiard::disc_segment_time(Vector(11, 3), Vector(0, -1), kNoGravity, Vector(-10, 0), Vector(10, 0), 1.0), kNever);
}

TEST(Segment, CeilingUnderGravityIsHitOnlyOnTheWayUp) {
  // Ceiling at y = 10, disc (radius 1) at y = 0 thrown up at 5 with g = -1: reaches y = 9 at
  // 5t - t^2/2 = 9 -> t = 5 - sqrt(7).
  const double t = billiard::disc_segment_time(Vector(0, 0), Vector(0, 5), Vector(0, -1), Vector(-10, 10), Vector(10, 10), 1.0);
  EXPECT_NEAR(t, 5 - std::sqrt(7.0), 1e-14);
  // Thrown at 4 it peaks at y = 8 and never touches.
  EXPECT_EQ(billiard::disc_segment_time(Vector(0, 0), Vector(0, 4), Vector(0, -1), Vector(-10, 10), Vector(10, 10), 1.0), kNever);
}

TEST(Point, DiscHitsTheEndOfASegment) {
  // Point at (0, 0), disc of radius 1 at (-5, 0) moving at speed 1: t = 4. Offset by 0.6 in y:
  // contact when dx^2 + 0.36 = 1, dx = -0.8, t = 4.2.
  EXPECT_DOUBLE_EQ(billiard::disc_point_time(Vector(-5, 0), Vector(1, 0), kNoGravity, Vector(0, 0), 1.0), 4.0);
  EXPECT_NEAR(billiard::disc_point_time(Vector(-5, 0.6), Vector(1, 0), kNoGravity, Vector(0, 0), 1.0), 4.2, 1e-14);
  // Falling onto a point from rest under gravity: 1 = h - t^2/2 with h = 3: t = 2.
  EXPECT_NEAR(billiard::disc_point_time(Vector(0, 3), Vector(0, 0), Vector(0, -1), Vector(0, 0), 1.0), 2.0, 1e-12);
}

TEST(Point, AHairInsideAndMovingOutTooSlowlyToGetClearCollidesNow) {
  // Overlapping the point by 1e-9 and rising at 1e-6 under g = 1: it rises 5e-13 and falls back
  // in without ever getting clear, so it is in contact now (it would pass into the point).
  EXPECT_EQ(billiard::disc_point_time(Vector(0, 1 - 1e-9), Vector(0, 1e-6), Vector(0, -1), Vector(0, 0), 1.0), 0.0);
  // Rising at 1e-3 it gets clear (5e-7 above) and lands back on the point at t = 2 v / g.
  EXPECT_NEAR(billiard::disc_point_time(Vector(0, 1 - 1e-12), Vector(0, 1e-3), Vector(0, -1), Vector(0, 0), 1.0), 2e-3, 1e-8);
}

TEST(Point, SlidingPastThePointAlongTheContactIsNoCollision) {
  // Touching the point on its left and moving straight down (along the contact), gravity down:
  // the tangent leads away from the point. A velocity off the tangent by 1e-17 (rounding) must
  // not count as approaching, or the disc would collide at once, again and again.
  for (const double off : {-1e-17, 0.0, 1e-17}) {
    EXPECT_EQ(billiard::disc_point_time(Vector(-1, 0), Vector(off, -1), Vector(0, -1), Vector(0, 0), 1.0), kNever) << off;
  }
  // Off by 1e-6 towards the point it is a real (glancing) collision: now.
  EXPECT_EQ(billiard::disc_point_time(Vector(-1, 0), Vector(1e-6, -1), Vector(0, -1), Vector(0, 0), 1.0), 0.0);
}

TEST(CellExit, LinearAndUnderGravity) {
  const Vector lo(0, 0), hi(2, 2);
  billiard::CellExit e = billiard::cell_exit_time(Vector(0.5, 1), Vector(1, 0.25), kNoGravity, lo, hi);
  EXPECT_DOUBLE_EQ(e.time, 1.5);  // x reaches 2 at 1.5 (y only at 4)
  EXPECT_EQ(e.axis, 0);
  EXPECT_EQ(e.direction, 1);
  // Thrown up at 1 from y = 1 with g = -1: peaks at 1.5 < 2, comes down to 0 at t = 1 + sqrt(3).
  e = billiard::cell_exit_time(Vector(1, 1), Vector(0, 1), Vector(0, -1), lo, hi);
  EXPECT_NEAR(e.time, 1 + std::sqrt(3.0), 1e-14);
  EXPECT_EQ(e.axis, 1);
  EXPECT_EQ(e.direction, -1);
  // At rest without gravity: never.
  EXPECT_EQ(billiard::cell_exit_time(Vector(1, 1), Vector(0, 0), kNoGravity, lo, hi).time, kNever);
}

TEST(Polynomial, FirstCrossingOfAQuarticWithFourRoots) {
  // (t-1)(t-2)(t-3)(t-4) = t^4 - 10 t^3 + 35 t^2 - 50 t + 24: positive at 0, first downward
  // crossing at 1, first upward at 2.
  const double p[5] = {24, -50, 35, -10, 1};
  EXPECT_NEAR(billiard::first_polynomial_crossing(p, 4, 10, false), 1.0, 1e-14);
  EXPECT_NEAR(billiard::first_polynomial_crossing(p, 4, 10, true), 2.0, 1e-14);
  EXPECT_EQ(billiard::first_polynomial_crossing(p, 4, 0.5, true), kNever);
}
