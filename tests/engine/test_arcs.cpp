// Curved walls (circular arcs): times of impact a person can check by hand, gravity cases against
// a direct numeric search, the arc as a wall of the engine, curved containers (stadium, Sinai
// billiard, mushroom, union of circles) over many collisions, and the argument checks.
#include "billiard/engine/simulation.hpp"
#include "billiard/engine/time_of_impact.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

using billiard::kNever;
using billiard::Vec2;

namespace {

const Vec2 kNoGravity = Vec2::Zero();
constexpr double kPi = 3.14159265358979323846;

// Is direction d on the arc from `start` counter-clockwise through `sweep`? Written with cross
// products, independently of the engine's angle arithmetic.
bool on_arc_by_cross_products(double start, double sweep, const Vec2& d) {
  if (sweep >= 2 * kPi) return true;
  const Vec2 s(std::cos(start), std::sin(start));
  const Vec2 e(std::cos(start + sweep), std::sin(start + sweep));
  const bool after_start = billiard::cross(s, d) >= 0;
  const bool before_end = billiard::cross(d, e) >= 0;
  return sweep <= kPi ? (after_start && before_end) : (after_start || before_end);
}

// Direct numeric search for the first contact of a disc with an arc: |r(t)| - reach sampled on
// a fine grid up to t_end, each sign change in the contact direction refined by bisection, the
// first one whose direction lies on the arc.
double numeric_arc_time(const Vec2& r, const Vec2& v, const Vec2& g, double rho, double start, double sweep,
                        double radius, double t_end) {
  auto at = [&](double t) -> Vec2 { return r + v * t + 0.5 * t * t * g; };
  struct Face {
    double reach;
    double sign;  // +1: contact when |r| rises to reach (concave); -1: when it falls (convex)
  };
  const Face faces[2] = {{rho - radius, +1}, {rho + radius, -1}};
  const int steps = 400000;
  double best = kNever;
  for (const Face& face : faces) {
    if (face.reach <= 0) continue;
    auto h = [&](double t) { return face.sign * (at(t).norm() - face.reach); };
    double t0 = 0, h0 = h(0);
    for (int k = 1; k <= steps; ++k) {
      const double t1 = t_end * k / steps, h1 = h(t1);
      if (h0 < 0 && h1 >= 0) {
        double lo = t0, hi = t1;
        for (int i = 0; i < 200; ++i) {
          const double mid = 0.5 * (lo + hi);
          (h(mid) < 0 ? lo : hi) = mid;
        }
        if (on_arc_by_cross_products(start, sweep, at(hi))) {
          best = std::min(best, hi);
          break;
        }
      }
      t0 = t1;
      h0 = h1;
    }
  }
  return best;
}

}  // namespace

// ---- Times of impact ----

TEST(ArcTime, DiscLeavingTheCentreOfAFullCircleHitsItAtReachOverSpeed) {
  // rho = 5, radius 1, speed 2: t = (rho - a) / |v| = 2, in any direction.
  for (const Vec2& v : {Vec2(2, 0), Vec2(1.2, 1.6), Vec2(0, -2)}) {
    EXPECT_DOUBLE_EQ(billiard::disc_arc_time(Vec2::Zero(), v, kNoGravity, 5, 0, 2 * kPi, 1), 2.0);
  }
}

TEST(ArcTime, DiscInsideHitsTheConcaveArcOnlyWhereTheArcIs) {
  // The right quarter of the circle rho = 5 (angles -45 to +45 degrees), a disc of radius 1 at
  // the centre: moving right it meets the arc at t = 4 / 2; moving left it leaves through the gap.
  EXPECT_DOUBLE_EQ(billiard::disc_arc_time(Vec2::Zero(), Vec2(2, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), 2.0);
  EXPECT_EQ(billiard::disc_arc_time(Vec2::Zero(), Vec2(-2, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), kNever);
  // From (0, 3) moving right: |r(t)|^2 = t^2 + 9 = 16 at t = sqrt(7), direction (sqrt 7, 3) at
  // 48.6 degrees: past the end of the arc, so no contact.
  EXPECT_EQ(billiard::disc_arc_time(Vec2(0, 3), Vec2(1, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), kNever);
  // From (0, 2): t = sqrt(12), direction at 30 degrees: on the arc.
  EXPECT_NEAR(billiard::disc_arc_time(Vec2(0, 2), Vec2(1, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), std::sqrt(12.0),
              1e-15);
}

TEST(ArcTime, ConvexObstacleAtGrazingDistanceAndJustInsideAndOutsideIt) {
  // Obstacle rho = 2, disc radius 1 moving right along y = b from x = -10: contact distance 3.
  const double rho = 2, a = 1;
  auto time_at = [&](double b) { return billiard::disc_arc_time(Vec2(-10, b), Vec2(1, 0), kNoGravity, rho, 0, 2 * kPi, a); };
  // Exactly grazing: touches at x = 0, t = 10 (no effect on the velocity, see the engine test).
  EXPECT_DOUBLE_EQ(time_at(3.0), 10.0);
  // Just inside: contact at x = -sqrt(9 - b^2).
  const double b = 3 - 1e-3;
  EXPECT_NEAR(time_at(b), 10 - std::sqrt(9 - b * b), 1e-12);
  // Just outside: never.
  EXPECT_EQ(time_at(3 + 1e-3), kNever);
  // Moving away: never; a hair inside the contact distance and approaching: now.
  EXPECT_EQ(billiard::disc_arc_time(Vec2(-4, 0), Vec2(-1, 0), kNoGravity, rho, 0, 2 * kPi, a), kNever);
  EXPECT_EQ(billiard::disc_arc_time(Vec2(-3 + 1e-15, 0), Vec2(1, 0), kNoGravity, rho, 0, 2 * kPi, a), 0.0);
}

TEST(ArcTime, GapsAndEndPoints) {
  // The upper half of the circle rho = 5 (angles 0 to 180 degrees), disc radius 0.5.
  const double rho = 5, a = 0.5, start = 0, sweep = kPi;
  auto time = [&](const Vec2& r, const Vec2& v) { return billiard::disc_arc_time(r, v, kNoGravity, rho, start, sweep, a); };
  // Moving right below the arc (y = -2): crosses the missing half twice, no contact.
  EXPECT_EQ(time(Vec2(-8, -2), Vec2(1, 0)), kNever);
  // From the centre straight down: out through the gap.
  EXPECT_EQ(time(Vec2::Zero(), Vec2(0, -1)), kNever);
  // From (0, -8) straight up: in through the gap, meets the inside of the arc at y = 4.5, t = 12.5.
  EXPECT_DOUBLE_EQ(time(Vec2(0, -8), Vec2(0, 1)), 12.5);
  // From (0, 8) straight down: the outside of the arc at y = 5.5, t = 2.5.
  EXPECT_DOUBLE_EQ(time(Vec2(0, 8), Vec2(0, -1)), 2.5);
  // Aimed at the end point (5, 0) from below: the arc itself is never touched (the end point is a
  // separate wall, met at t = 3 - 0.5 = 2.5).
  EXPECT_EQ(time(Vec2(5, -3), Vec2(0, 1)), kNever);
  EXPECT_DOUBLE_EQ(billiard::disc_point_time(Vec2(5, -3), Vec2(0, 1), kNoGravity, Vec2(5, 0), a), 2.5);
}

TEST(ArcTime, RoundingConventionOnBothFaces) {
  // A hair beyond the concave contact (|r| = 4.5 + 1e-15) moving out: now; moving in: later.
  const Vec2 r(4.5 + 1e-15, 0);
  EXPECT_EQ(billiard::disc_arc_time(r, Vec2(1, 0), kNoGravity, 5, -1, 2, 0.5), 0.0);
  EXPECT_GT(billiard::disc_arc_time(r, Vec2(-1, 0), kNoGravity, 5, -1, 2, 0.5), 8.9);
  // Just bounced off the convex face (|r| = 5.5 exactly, moving out): never.
  EXPECT_EQ(billiard::disc_arc_time(Vec2(5.5, 0), Vec2(1, 0.3), kNoGravity, 5, -1, 2, 0.5), kNever);
}

TEST(ArcTime, UnderGravityADiscDroppedIntoACupFallsThroughTheOpenTop) {
  // The lower half of rho = 5 (angles 180 to 360 degrees) as a cup; a disc of radius 0.5 at rest
  // at (1, 8), g = (0, -1): it falls through the open top and meets the inside of the cup at
  // y = -sqrt(4.5^2 - 1), after falling 8 + sqrt(19.25): t = sqrt(2 (8 + sqrt(19.25))).
  const double t = billiard::disc_arc_time(Vec2(1, 8), Vec2::Zero(), Vec2(0, -1), 5, kPi, kPi, 0.5);
  EXPECT_NEAR(t, std::sqrt(2 * (8 + std::sqrt(19.25))), 1e-12);
}

TEST(ArcTime, UnderGravityThrownUpThroughTheGapIntoADome) {
  // The upper half of rho = 5 as a dome, disc radius 0.5 thrown up from (0, -8) at speed 6, g = 1:
  // y(t) = -8 + 6 t - t^2 / 2 reaches 4.5 (inside the dome) at t = 6 - sqrt(11).
  const double t = billiard::disc_arc_time(Vec2(0, -8), Vec2(0, 6), Vec2(0, -1), 5, 0, kPi, 0.5);
  EXPECT_NEAR(t, 6 - std::sqrt(11.0), 1e-12);
}

TEST(ArcTime, UnderGravityAgreesWithADirectNumericSearch) {
  // Throws past arcs of several shapes: some pass the gap and come back onto the other face.
  struct Case {
    Vec2 r, v, g;
    double rho, start, sweep, radius;
  };
  const Case cases[] = {
      {Vec2(7, -1), Vec2(-0.8, 6), Vec2(0, -1), 5, 0, kPi, 0.5},        // over the end, onto the dome
      {Vec2(0, -8), Vec2(0.7, 6.5), Vec2(0, -1), 5, 0, kPi, 0.5},       // up into the dome, off centre
      {Vec2(-9, 2), Vec2(3, 1), Vec2(0.2, -1), 4, kPi / 3, kPi, 0.3},   // tilted gravity, left arc
      {Vec2(1, 1), Vec2(2, 0.5), Vec2(0, -2), 3, -kPi / 2, 1.5 * kPi, 0.25},  // inside a 3/4 circle
      {Vec2(0, 6), Vec2(-0.5, 0), Vec2(0, -1), 3, 0, 2 * kPi, 1},       // onto a full circle obstacle
  };
  for (const Case& c : cases) {
    const double t = billiard::disc_arc_time(c.r, c.v, c.g, c.rho, c.start, c.sweep, c.radius);
    const double expected = numeric_arc_time(c.r, c.v, c.g, c.rho, c.start, c.sweep, c.radius, 40);
    ASSERT_LT(expected, kNever) << "the case must have a contact before t = 40";
    // The grid search finds the contact to the bisection's precision unless two sign changes
    // fall within one step (1e-4): none do here.
    EXPECT_NEAR(t, expected, 1e-9 * (1 + expected)) << "r = (" << c.r.x() << ", " << c.r.y() << ")";
  }
}
