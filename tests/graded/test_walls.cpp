// Graded tests of task 8, `propagate_walls`: one event step of hard circles on a circular table
// with straight walls (segments, hit on either face and at their end points) inside it.
//
// What is checked, and how:
//   1. hand-computed cases (a face from either side, at an angle, an end point glancing and
//      head-on, a circle passing just beside an end point, a wall of zero length, a circle
//      sliding along a wall, no re-collision after a bounce, a circle knocked against a wall);
//   2. the earliest event among walls, the table and pairs;
//   3. step by step agreement, from shared states, with the oracle of task 4 (no walls) and with
//      the finished library (billiard::Simulation) on random wall layouts. The dynamics is
//      chaotic (rounding grows ~1e10-fold in 1000 events), so only single steps from the same
//      state are compared, never whole trajectories; events within 1e-9 of the time scale of
//      each other are ties that rounding may order either way;
//   4. long runs of the student's own trajectory: <v^2> conserved, no overlaps, nobody leaves
//      the table, comes closer to a wall than circle_radius, crosses a wall spanning the table
//      or leaves a closed triangle of walls, times finite and >= 0, no immediate repeats;
//   5. argument errors: std::invalid_argument naming the argument, state unchanged.
// Tolerances are for rounding only: hand-made cases have numbers of order 1 to 10, so double
// precision gives ~1e-15 and the tests allow 1e-12; single steps allow 1e-9 relative (the
// library computes in a different order); long runs allow 1e-9 of the table for positions and
// 1e-11 relative for <v^2>, which random-walks by ~1e-16 per collision.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"
#include "walls_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// A failing test draws the step that went wrong (support/failure_pictures.hpp).
const bool kPicturesJudged = billiard::testing::register_step_judge("propagate_walls", billiard::testing::walls_judgement);

using billiard::Collision;
using billiard::Coordinates;
using billiard::kWall;
using billiard::Vector;
using billiard::Velocities;
using billiard::Wall;
using billiard::wall_id;
using billiard::testing::explain;
using billiard::testing::row;
using billiard::testing::text;
using billiard::testing::wall;
using billiard::testing::WallTable;

constexpr double kTol = 1e-12;

const char* const kHintWallId =
    "report a hit of walls[k], on a face or at an end point, as other = wall_id(k) = -2 - k; kWall (-1) is only the "
    "table's rim, and rows >= 0 are circles.";
const char* const kHintFaceTime =
    "a circle touches a face when the signed distance of its centre from the wall's line, d(t) = d0 + (v.n) t with "
    "d0 = (r - a).n and n a unit normal (perpendicular to b - a, divided by the wall's length), reaches "
    "circle_radius in size while approaching the line: t = (|d0| - circle_radius) / |v.n|.";
const char* const kHintFaceReflection =
    "at a face reverse only the velocity component along the wall's unit normal n: v' = v - 2 (v.n) n; the "
    "component along the wall is kept. Reversing the whole velocity (v' = -v) is right only for a head-on hit.";
const char* const kHintBothFaces =
    "a wall has two faces: a circle on either side can hit it. Use |d0| and require only that the circle moves "
    "towards the line (d0 and v.n of opposite signs), whatever the sign of d0.";
const char* const kHintSegment =
    "the wall is a segment, not an infinite line: a face hit counts only if the foot of the perpendicular from the "
    "centre at contact lies between a and b, 0 <= (r + v t - a).(b - a) / |b - a| <= |b - a|. Beyond the ends the "
    "end points take over.";
const char* const kHintEndPoint =
    "a circle passing the end of a wall hits its end point p like a circle of radius 0: solve |r - p + v t| = "
    "circle_radius (the pair formula of propagate with contact distance circle_radius, approaching only, stable "
    "form) for both end points of every wall.";
const char* const kHintPointNormal =
    "at an end point p the normal is the line from p to the centre at contact, n = (r - p) / |r - p|, not the "
    "wall's normal: v' = v - 2 (v.n) n.";
const char* const kHintZeroLength =
    "a wall of zero length (a == b) has no direction: (b - a) / |b - a| is 0 / 0. Skip its faces and keep its end "
    "point, which a circle hits like any other end point.";
const char* const kHintParallel =
    "a circle moving parallel to a wall (v.n = 0) never hits its face, even while touching it: check that the "
    "circle moves towards the line (d0 (v.n) < 0) before dividing by v.n.";
const char* const kHintApproach =
    "right after a bounce the circle touches the wall (|d0| = circle_radius up to rounding) but moves away from "
    "it: only a circle moving towards the line (d0 (v.n) < 0) can hit a face, and only one moving towards an end "
    "point ((r - p).v < 0) can hit the point. Check the direction of motion, not a time epsilon.";
const char* const kHintTouchingNow =
    "a circle touching a wall and moving towards it must hit it at t = 0: accept t = 0 (clamp tiny negative times "
    "from rounding to 0). A time epsilon (t > 1e-9) instead of the direction check lets it pass through the wall.";
const char* const kHintEarliest =
    "compute the time of every possible event (each circle with the table, with each wall's faces and end points, "
    "and each pair of circles) and process the smallest; the order of walls and circles does not matter.";
const char* const kHintMoveAll =
    "every circle moves in a straight line during the step, r += v * t, including the ones that do not collide.";
const char* const kHintSwap =
    "between circles exchange only the velocity components along the line of centres, as in propagate.";
const char* const kHintTableTime =
    "a circle touches the table's rim when |r + v t| = table_radius - circle_radius: the positive root, as in "
    "propagate.";

std::string describe(const Collision& c, const WallTable& t) {
  return billiard::testing::describe_walls_collision(c, static_cast<int>(t.walls.size()));
}

// Calls the student's propagate_walls. Results wrong in every test (a negative or NaN time, a
// circle with itself) are reported first, so that the first message names the mistake.
Collision step(WallTable& t) {
  const Collision got = billiard::testing::recorded_walls_step(t.R, t.a, t.n(), t.c, t.v, t.walls);
  if (std::isnan(got.time)) {
    ADD_FAILURE() << explain("a collision time that is a number", text("returned ", describe(got, t)),
                             "a NaN time comes from 0 / 0: a circle moving parallel to a wall (v.n = 0), a wall of "
                             "zero length (|b - a| = 0) or a circle at rest. Check these before dividing.");
  } else if (got.time < 0) {
    ADD_FAILURE() << explain("the time until the next collision, which is never negative",
                             text("returned ", describe(got, t)),
                             "a negative time is a contact in the past: only circles moving towards a wall, an "
                             "end point or another circle can collide, and tiny negative times from rounding are 0.");
  }
  if (got.other == got.circle) {
    ADD_FAILURE() << explain("a collision of two different circles, or of a circle with a wall or the table",
                             text("returned ", describe(got, t)), "a circle cannot collide with itself.");
  }
  return got;
}

// Calls step and turns an std::invalid_argument on a valid state into a test failure.
bool checked_step(WallTable& t, Collision& got, const std::string& where) {
  try {
    got = step(t);
    return true;
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(text("propagate_walls to accept a valid state and find its next collision (", where, ")"),
                             text("it threw std::invalid_argument: \"", error.what(), "\""),
                             "after a bounce a circle touches the wall up to rounding; the checks:: functions allow "
                             "for that. If no event was found, a circle has escaped through a wall or the table.");
    return false;
  }
}

WallTable one_circle(double x, double y, double vx, double vy, std::vector<Wall> walls) {
  WallTable t;
  t.R = 10;
  t.a = 1;
  t.c = Coordinates(1, 2);
  t.v = Velocities(1, 2);
  t.c << x, y;
  t.v << vx, vy;
  t.walls = std::move(walls);
  return t;
}

void expect_row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int i, double x, double y,
                const std::string& what, const std::string& hint) {
  const double error = std::hypot(rows(i, 0) - x, rows(i, 1) - y);
  EXPECT_LE(error, kTol) << explain(text(what, " to be (", x, ", ", y, ") (within ", kTol, ")"),
                                    text("it is ", row(rows, i)), hint);
}

bool is_wall_hit(const Collision& c, int circle, int k) { return c.circle == circle && c.other == wall_id(k); }
bool near(double x, double y, double tolerance = kTol) { return std::abs(x - y) <= tolerance; }

// Expects circle 0 to hit walls[k] at `time`, at (x, y), leaving with (vx, vy). The hints for
// the event and the time come from `event_hint` (given what was returned).
void expect_wall_hit(WallTable& t, int k, double time, double x, double y, double vx, double vy,
                     const std::string& situation, const std::function<std::string(const Collision&)>& event_hint,
                     const std::string& reflection_hint) {
  const Collision got = step(t);
  if (!is_wall_hit(got, 0, k) || !near(got.time, time)) {
    ADD_FAILURE() << explain(text("circle 0 to hit walls[", k, "] (other = wall_id(", k, ") = ", wall_id(k),
                                  ") after time ", time, ": ", situation),
                             text("returned ", describe(got, t)), event_hint(got));
    return;
  }
  expect_row(t.c, 0, x, y, "the circle's centre at contact", kHintMoveAll);
  expect_row(t.v, 0, vx, vy, "the velocity after the bounce", reflection_hint);
}

// The hint for a face hit that went wrong: a kWall at the right time is only the wrong id.
std::function<std::string(const Collision&)> face_hint(double time, const char* otherwise) {
  return [time, otherwise](const Collision& got) -> std::string {
    if (got.circle == 0 && got.other == kWall && near(got.time, time)) return kHintWallId;
    return otherwise;
  };
}

// ---------------------------------------------------------------------------------------------
// 1. Hand-computed cases.

GRADED_TEST(Walls, CircleFromCentreHitsWallFaceAtTimeThree, 2, visible) {
  // Wall along y = 4 from x = 5 to -5; a circle of radius 1 from the origin moving (0, 1)
  // touches it when its centre reaches y = 3: time 3. Head-on, so it comes back with (0, -1).
  WallTable t = one_circle(0, 0, 0, 1, {wall(5, 4, -5, 4)});
  expect_wall_hit(t, 0, 3, 0, 3, 0, -1, "a circle from (0, 0) moving (0, 1) towards a wall along y = 4",
                  face_hint(3, kHintFaceTime), kHintFaceReflection);
}

GRADED_TEST(Walls, CircleHitsTheOtherFaceOfTheWall, 2, visible) {
  // The same wall from above: from (0, 8) moving (0, -1) the centre reaches y = 5 at time 3.
  // (Its signed distance d0 = (r - a).n has the opposite sign to the previous test's.)
  WallTable t = one_circle(0, 8, 0, -1, {wall(5, 4, -5, 4)});
  expect_wall_hit(t, 0, 3, 0, 5, 0, 1, "a circle from (0, 8) moving (0, -1) towards the upper face of a wall along y = 4",
                  face_hint(3, kHintBothFaces), kHintFaceReflection);
}

GRADED_TEST(Walls, ObliqueFaceHitReflectsOnlyTheNormalComponent, 2, visible) {
  // Wall from (2, -4) to (8, 4): direction u = (0.6, 0.8), unit normal n = (-0.8, 0.6); the
  // origin is d0 = 4 from its line. Moving (1, 0), v.n = -0.8: contact at t = (4 - 1) / 0.8 =
  // 3.75, centre (3.75, 0), foot 4.25 along the wall (of length 10). v' = v - 2 (v.n) n =
  // (1, 0) - 1.6 (0.8, -0.6) = (-0.28, 0.96).
  WallTable t = one_circle(0, 0, 1, 0, {wall(2, -4, 8, 4)});
  expect_wall_hit(t, 0, 3.75, 3.75, 0, -0.28, 0.96, "a circle from (0, 0) moving (1, 0) towards a slanted wall",
                  face_hint(3.75, kHintFaceTime), kHintFaceReflection);
}

GRADED_TEST(Walls, GlancingHitOfAnEndPoint, 3, visible) {
  // Wall from (0, 0) down to the rim at (0, -10). A circle moving (1, 0) along y = 0.6 passes
  // above the wall's upper end (0, 0) and grazes it: |(-5 + t, 0.6)| = 1 at x = -0.8, t = 4.2.
  // The normal there is (r - p) / |r - p| = (-0.8, 0.6), so v' = (1, 0) - 2 (-0.8) (-0.8, 0.6)
  // = (-0.28, 0.96). (The wall's infinite line x = 0 would be reached at t = 4, at y = 0.6,
  // beyond the segment.)
  WallTable t = one_circle(-5, 0.6, 1, 0, {wall(0, 0, 0, -10)});
  expect_wall_hit(
      t, 0, 4.2, -0.8, 0.6, -0.28, 0.96, "a circle from (-5, 0.6) moving (1, 0) past the end point (0, 0) of a wall",
      [](const Collision& got) -> std::string {
        if (got.other == wall_id(0) && near(got.time, 4, 1e-9)) return kHintSegment;
        if (got.other == kWall && near(got.time, 4.2)) return kHintWallId;
        return kHintEndPoint;
      },
      kHintPointNormal);
}

GRADED_TEST(Walls, HeadOnHitOfAnEndPointAlongTheWall, 2, after_due_date) {
  // A circle moving along the wall's own line towards its end point (0, 0): contact at x = -1,
  // time 4, normal (-1, 0): it comes straight back. (It never touches the faces: v.n = 0.)
  WallTable t = one_circle(-5, 0, 1, 0, {wall(0, 0, 6, 0)});
  expect_wall_hit(
      t, 0, 4, -1, 0, -1, 0, "a circle from (-5, 0) moving (1, 0) along the line of a wall from (0, 0) to (6, 0)",
      [](const Collision& got) -> std::string { return got.other == kWall && near(got.time, 4) ? kHintWallId : kHintEndPoint; },
      kHintPointNormal);
}

GRADED_TEST(Walls, CirclePassingJustBesideAnEndPointMissesIt, 2, after_due_date) {
  // Along y = 1.001 the circle passes the end point (0, 0) at distance 1.001 > a = 1: no wall
  // hit; it reaches the rim where |(x, 1.001)| = 9.
  WallTable t = one_circle(-5, 1.001, 1, 0, {wall(0, 0, 0, -10)});
  const double time = 5 + std::sqrt(81 - 1.001 * 1.001);
  const Collision got = step(t);
  if (!(got.circle == 0 && got.other == kWall && near(got.time, time))) {
    ADD_FAILURE() << explain(text("circle 0 to pass the end point (0, 0) at distance 1.001 and hit the table's rim "
                                  "after time ",
                                  time),
                             text("returned ", describe(got, t)),
                             got.other == wall_id(0) && near(got.time, 4, 1e-9)
                                 ? kHintSegment
                                 : "an end point is hit only if the circle's centre comes within circle_radius of it: "
                                   "when the discriminant b^2 - v.v c of |r - p + v t| = a is negative, it passes.");
  }
}

GRADED_TEST(Walls, HitExactlyAtAnEndPoint, 2, after_due_date) {
  // Head-on towards a face whose foot at contact is exactly an end point: the face and the end
  // point are touched at the same moment, with the same normal (0, +-1); either gives the same
  // bounce. Checked at end point a and at end point b.
  struct Case {
    double y, vy;
    Wall w;
  };
  const Case cases[] = {{-5, 1, wall(0, 0, 6, 0)}, {5, -1, wall(-6, 0, 0, 0)}};
  for (const Case& k : cases) {
    WallTable t = one_circle(0, k.y, 0, k.vy, {k.w});
    expect_wall_hit(t, 0, 4, 0, k.y + 4 * k.vy, 0, -k.vy,
                    text("a circle from (0, ", k.y, ") moving (0, ", k.vy, ") onto the end (0, 0) of the wall"),
                    [](const Collision& got) -> std::string {
                      return got.other == kWall && near(got.time, 4) ? kHintWallId
                             : got.other == kWall
                                 ? "when the foot of the perpendicular lies exactly at an end point, the face and the "
                                   "end point are touched together: include both ends of the segment (0 <= s <= "
                                   "length) and keep the end points as obstacles of their own."
                                 : kHintEndPoint;
                    },
                    kHintFaceReflection);
  }
}

GRADED_TEST(Walls, WallOfZeroLengthIsAPoint, 2, after_due_date) {
  // a == b == (0, 0): only the point is there; the glancing hit of GlancingHitOfAnEndPoint.
  WallTable t = one_circle(-5, 0.6, 1, 0, {wall(0, 0, 0, 0)});
  expect_wall_hit(t, 0, 4.2, -0.8, 0.6, -0.28, 0.96, "a circle from (-5, 0.6) moving (1, 0) past a wall of zero length at (0, 0)",
                  [](const Collision& got) -> std::string {
                    return got.other == kWall && near(got.time, 4.2) ? kHintWallId : kHintZeroLength;
                  },
                  kHintPointNormal);
}

GRADED_TEST(Walls, CircleSlidingAlongAWallNeverHitsIt, 2, after_due_date) {
  // A wall across the whole table along y = 0 (its ends on the rim). A circle touching it and
  // moving parallel to it (v.n = 0) slides along it until it meets the rim, where
  // |(t, 1)| = 9: time sqrt(80). Both sides.
  for (const double side : {1.0, -1.0}) {
    WallTable t = one_circle(0, side, side, 0, {wall(-10, 0, 10, 0)});
    const Collision got = step(t);
    if (!(got.circle == 0 && got.other == kWall && near(got.time, std::sqrt(80.0)))) {
      ADD_FAILURE() << explain(text("a circle at (0, ", side, ") touching a wall along y = 0 and moving (", side,
                                    ", 0) along it to hit only the rim, after time sqrt(80) = ", std::sqrt(80.0)),
                               text("returned ", describe(got, t)), kHintParallel);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 2. No re-collision right after a bounce; a circle touching a wall and approaching hits it now.

GRADED_TEST(Walls, NoRecollisionRightAfterAFaceHit, 2, visible) {
  // After the hit of CircleFromCentreHitsWallFaceAtTimeThree the circle leaves (0, 3) with
  // (0, -1): the next event is the rim at (0, -9), 12 later.
  WallTable t = one_circle(0, 0, 0, 1, {wall(5, 4, -5, 4)});
  step(t);
  const Collision got = step(t);
  EXPECT_TRUE(got.circle == 0 && got.other == kWall && near(got.time, 12))
      << explain("the second step to be the rim at (0, -9) after time 12", text("returned ", describe(got, t)),
                 kHintApproach);
}

GRADED_TEST(Walls, NoRecollisionRightAfterAnEndPointHit, 2, after_due_date) {
  // After the glancing hit at (-0.8, 0.6) the circle leaves with (-0.28, 0.96) and meets the
  // rim when |(-0.8 - 0.28 t, 0.6 + 0.96 t)| = 9: t = -0.8 + sqrt(80.64).
  WallTable t = one_circle(-5, 0.6, 1, 0, {wall(0, 0, 0, -10)});
  step(t);
  const Collision got = step(t);
  const double time = -0.8 + std::sqrt(80.64);
  EXPECT_TRUE(got.circle == 0 && got.other == kWall && near(got.time, time, 1e-10))
      << explain(text("the second step to be the rim after time ", time), text("returned ", describe(got, t)),
                 kHintApproach);
}

GRADED_TEST(Walls, CircleKnockedAgainstAWallBouncesBackAtOnce, 2, visible) {
  // Circle 0 rests touching the wall y = 4 at (0, 3); circle 1 comes from (0, -2) at speed 1.
  // Step 1: they collide at time 3 and circle 0 takes (0, 1) while touching the wall.
  // Step 2: circle 0 bounces off the wall at once (time 0). Step 3: it hits circle 1 at once.
  // Step 4: circle 1 goes from (0, 1) down to the rim at (0, -9): time 10.
  WallTable t;
  t.c = Coordinates(2, 2);
  t.v = Velocities(2, 2);
  t.c << 0, 3, 0, -2;
  t.v << 0, 0, 0, 1;
  t.walls = {wall(-5, 4, 5, 4)};
  struct Expected {
    double time;
    int circle, other;
    const char* what;
    const char* hint;
  };
  const Expected expected[] = {
      {3, 0, 1, "circle 1 to hit circle 0 (resting against the wall) at time 3", kHintSwap},
      {0, 0, wall_id(0), "circle 0, now touching the wall and moving towards it, to bounce off it at time 0",
       kHintTouchingNow},
      {0, 0, 1, "circle 0, bouncing back, to hit the touching circle 1 at time 0", kHintTouchingNow},
      {10, 1, kWall, "circle 1 to go down to the rim at (0, -9) after time 10", kHintTableTime},
  };
  for (int s = 0; s < 4; ++s) {
    const Expected& e = expected[s];
    Collision got{};
    try {
      got = step(t);
    } catch (const std::invalid_argument& error) {
      ADD_FAILURE() << explain(text("step ", s + 1, ": ", e.what),
                               text("it threw std::invalid_argument: \"", error.what(), "\""), e.hint);
      return;
    }
    const bool same = got.circle == e.circle ? got.other == e.other : (got.circle == e.other && got.other == e.circle);
    if (!same || !near(got.time, e.time)) {
      ADD_FAILURE() << explain(text("step ", s + 1, ": ", e.what), text("returned ", describe(got, t)), e.hint);
      return;
    }
  }
  expect_row(t.v, 1, 0, 1, "circle 1's velocity after bouncing off the rim", kHintFaceReflection);
}

// ---------------------------------------------------------------------------------------------
// 3. The earliest event.

GRADED_TEST(Walls, EarliestOfSeveralWallsIsChosen, 2, after_due_date) {
  // From the origin moving (1, 0): walls[0] at x = 6 (time 5), walls[1] at x = 3 (time 2),
  // walls[2] at x = -2 behind the circle, walls[3] along y = 2 parallel to the motion.
  WallTable t = one_circle(0, 0, 1, 0, {wall(6, -5, 6, 5), wall(3, -5, 3, 5), wall(-2, -5, -2, 5), wall(-5, 2, 5, 2)});
  const Collision got = step(t);
  EXPECT_TRUE(is_wall_hit(got, 0, 1) && near(got.time, 2))
      << explain("circle 0 to hit walls[1] (at x = 3) after time 2; walls[0] is farther, walls[2] behind, walls[3] "
                 "parallel",
                 text("returned ", describe(got, t)), got.other == wall_id(2) ? kHintApproach : kHintEarliest);
}

GRADED_TEST(Walls, WallHitsAndCircleCollisionsInTimeOrder, 2, after_due_date) {
  // Circles 1 and 2 collide head-on at time 4; circle 0 from the origin moving (0, 1) reaches
  // a wall along y = 4 at time 3 (first), or along y = 6 at time 5 (after the pair).
  for (const double y : {4.0, 6.0}) {
    WallTable t;
    t.c = Coordinates(3, 2);
    t.v = Velocities(3, 2);
    t.c << 0, 0, -5, -3, 5, -3;
    t.v << 0, 1, 1, 0, -1, 0;
    t.walls = {wall(-5, y, 5, y)};
    const Collision got = step(t);
    const bool wall_first = y < 5;
    const bool ok = wall_first ? is_wall_hit(got, 0, 0) && near(got.time, 3)
                               : ((got.circle == 1 && got.other == 2) || (got.circle == 2 && got.other == 1)) &&
                                     near(got.time, 4);
    EXPECT_TRUE(ok) << explain(wall_first ? "circle 0 to hit the wall along y = 4 at time 3, before circles 1 and 2 "
                                            "collide at time 4"
                                          : "circles 1 and 2 to collide at time 4, before circle 0 reaches the wall "
                                            "along y = 6 at time 5",
                               text("returned ", describe(got, t)), kHintEarliest);
  }
}

// ---------------------------------------------------------------------------------------------
// 4. Step by step against independent implementations, from shared states.

GRADED_TEST(Walls, WithoutWallsMatchesPropagateStepByStep, 3, after_due_date) {
  // walls = {} is task 4: compared with the oracle of propagate's suite (long double, every
  // event within the tie window accepted) on 16 random tables, 60 steps each.
  const double radii[] = {10.0, 1.0, 3.7, 250.0};
  for (int k = 0; k < 16; ++k) {
    const double R = radii[k % 4];
    const int n = 1 + (k * 5) % 24;
    const double a = R * std::sqrt(0.02 + 0.01 * (k % 10)) / std::sqrt(static_cast<double>(n));
    Coordinates c = billiard::testing::scattered_circles(R, a, n, 700 + static_cast<std::uint64_t>(k));
    Velocities v = billiard::testing::gaussian_velocities(n, 800 + static_cast<std::uint64_t>(k)) * (k % 3 == 0 ? 0.1 : 3.0);
    const double scale = R / std::sqrt(v.squaredNorm());
    for (int e = 0; e < 60; ++e) {
      const auto expected = billiard::testing::oracle_step(R, a, c, v, 1e-9 * scale);
      WallTable t;
      t.R = R;
      t.a = a;
      t.c = c;
      t.v = v;
      const std::string where = text("a table without walls ", k, " (n = ", n, ", R = ", R, "), step ", e);
      Collision got{};
      if (!checked_step(t, got, where)) return;
      const billiard::testing::OracleEvent* match = nullptr;
      for (const auto& event : expected.events) {
        if (billiard::testing::same_event(event, got)) match = &event;
      }
      const auto& first = expected.events.front();
      if (match == nullptr || !(std::abs(got.time - match->time) <= 1e-9 * (match->time + scale))) {
        ADD_FAILURE() << explain(text("at ", where, ": ", billiard::testing::describe_event(first.circle, first.other),
                                      " after time ", first.time),
                                 text("returned ", describe(got, t)),
                                 "with no walls propagate_walls is propagate: the table and the pairs, as in task 4.");
        return;
      }
      const double position_error = (t.c - match->coordinates).rowwise().norm().maxCoeff();
      const double velocity_error = (t.v - match->velocities).rowwise().norm().maxCoeff();
      if (!(position_error <= 1e-9 * R) || !(velocity_error <= 1e-9 * std::sqrt(v.squaredNorm()))) {
        ADD_FAILURE() << explain(text("at ", where, ": the state after ", billiard::testing::describe_event(match->circle, match->other)),
                                 text("positions off by up to ", position_error, ", velocities by up to ", velocity_error),
                                 "move every circle by v t, then change the colliding circles' velocities as in "
                                 "propagate.");
        return;
      }
      billiard::testing::oracle_advance(expected, c, v);
    }
  }
}

std::string library_hint(const std::string& what, bool wall_event) {
  if (what == "event") return kHintEarliest;
  if (what == "time") return wall_event ? kHintFaceTime : "the pair and table times are those of propagate.";
  if (what == "position") return kHintMoveAll;
  return wall_event ? "at a face reflect along the wall's unit normal, at an end point p along (r - p) / |r - p|, at "
                      "the rim along r / |r|: v' = v - 2 (v.n) n."
                    : kHintSwap;
}

GRADED_TEST(Walls, MatchesTheLibraryStepByStepOnRandomWallLayouts, 3, after_due_date) {
  // 60 random tables (R from 1 to 250, 1 to 20 circles, 1 to 4 walls, speeds 0.02 to 30; chains,
  // crossings, V shapes, walls from the rim), 100 steps each.
  for (int k = 0; k < 60; ++k) {
    if (!billiard::testing::matches_library(billiard::testing::random_wall_table(k, 0), 100, library_hint)) return;
  }
}

// A closed triangle of walls (corners shared, at radius 9 of a table of radius 10), with circles
// inside and outside it.
WallTable triangle_table(int inside, int outside, std::uint64_t seed) {
  WallTable t;
  t.R = 10;
  t.a = 0.5;
  const Vector p0 = billiard::testing::on_rim(9, billiard::testing::kPi / 2);
  const Vector p1 = billiard::testing::on_rim(9, billiard::testing::kPi * 7 / 6);
  const Vector p2 = billiard::testing::on_rim(9, billiard::testing::kPi * 11 / 6);
  t.walls = {Wall{p0, p1}, Wall{p1, p2}, Wall{p2, p0}};
  auto in_triangle = [walls = t.walls](const Vector& p) {
    return billiard::testing::side_of(p, walls[0]) > 0 && billiard::testing::side_of(p, walls[1]) > 0 &&
           billiard::testing::side_of(p, walls[2]) > 0;
  };
  const Coordinates in = billiard::testing::place_circles(t.R, t.a, inside, t.walls, seed, in_triangle);
  std::vector<Wall> with_inside = t.walls;
  for (Eigen::Index i = 0; i < in.rows(); ++i) with_inside.push_back(Wall{in.row(i), in.row(i)});
  // Outside circles: clear of the walls, and of the inside circles (zero-length walls 2a wide).
  const Coordinates out = billiard::testing::place_circles(
      t.R, t.a, outside, t.walls, seed + 1,
      [&](const Vector& p) {
        if (in_triangle(p)) return false;
        for (Eigen::Index i = 0; i < in.rows(); ++i) {
          if ((p - in.row(i)).norm() < 2 * t.a * (1 + 1e-6)) return false;
        }
        return true;
      });
  t.c = Coordinates(in.rows() + out.rows(), 2);
  t.c << in, out;
  t.v = billiard::testing::gaussian_velocities(t.n(), seed + 2);
  t.label = text("a closed triangle of walls with ", in.rows(), " circles inside and ", out.rows(), " outside");
  return t;
}

GRADED_TEST(Walls, MatchesTheLibraryWhereWallsMeetCrossOrTouchTheRim, 3, after_due_date) {
  // Hand-made layouts: a closed triangle (shared corners); a star of four walls from the centre
  // to the rim; a square with an X inside; a chord across the table. 150 steps each.
  std::vector<WallTable> tables;
  tables.push_back(triangle_table(6, 6, 61));
  {
    WallTable t;
    t.R = 10;
    t.a = 0.6;
    t.walls = {wall(0, 0, 10, 0), wall(0, 0, 0, 10), wall(0, 0, -10, 0), wall(0, 0, 0, -10)};
    t.c = billiard::testing::place_circles(t.R, t.a, 12, t.walls, 62);
    t.v = billiard::testing::gaussian_velocities(t.n(), 63);
    t.label = "a star of four walls from the centre to the rim";
    tables.push_back(t);
  }
  {
    WallTable t;
    t.R = 5;
    t.a = 0.3;
    t.walls = {wall(-3, -3, 3, -3), wall(3, -3, 3, 3), wall(3, 3, -3, 3), wall(-3, 3, -3, -3),
               wall(-2, -2, 2, 2), wall(-2, 2, 2, -2)};
    t.c = billiard::testing::place_circles(t.R, t.a, 14, t.walls, 64);
    t.v = billiard::testing::gaussian_velocities(t.n(), 65) * 2.0;
    t.label = "a square of walls with an X of walls inside";
    tables.push_back(t);
  }
  {
    WallTable t;
    t.R = 10;
    t.a = 0.8;
    t.walls = {Wall{billiard::testing::on_rim(10, 0.4), billiard::testing::on_rim(10, 2.9)}};
    t.c = billiard::testing::place_circles(t.R, t.a, 10, t.walls, 66);
    t.v = billiard::testing::gaussian_velocities(t.n(), 67);
    t.label = "a chord across the whole table";
    tables.push_back(t);
  }
  for (const WallTable& t : tables) {
    if (!billiard::testing::matches_library(t, 150, library_hint)) return;
  }
}

// ---------------------------------------------------------------------------------------------
// 5. Long runs of the student's own trajectory.

// 30 circles in a table split by a chord across it (walls[0]), a V, an X, a wall from the rim
// and a wall of zero length.
WallTable long_run_table() {
  WallTable t;
  t.R = 10;
  t.a = 0.35;
  const double x = std::sqrt(100.0 - 4.0);
  t.walls = {wall(-x, 2, x, 2),     wall(-4, -3, 0, -6), wall(0, -6, 4, -3), wall(-3, 5, 3, 7),
             wall(-3, 7, 3, 5),     Wall{billiard::testing::on_rim(10, -0.3), Vector(5, -1)},
             wall(-6, -2, -6, -2)};
  t.c = billiard::testing::place_circles(t.R, t.a, 30, t.walls, 4242);
  t.v = billiard::testing::gaussian_velocities(t.n(), 4242);
  t.label = "the long run (30 circles, a chord across the table, a V, an X, a wall from the rim, a point)";
  return t;
}

#ifdef NDEBUG
constexpr int kLongRunEvents = 2000;
#else
constexpr int kLongRunEvents = 300;  // Debug and sanitizer builds are ~100 times slower
#endif

long double mean_square(const Velocities& v) {
  long double sum = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) sum += static_cast<long double>(v.row(i).squaredNorm());
  return sum / static_cast<long double>(v.rows());
}

GRADED_TEST(Walls, LongRunConservesMeanSquaredVelocity, 3, after_due_date) {
  WallTable t = long_run_table();
  const long double start = mean_square(t.v);
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text(t.label, ", collision ", e))) return;
    const double drift = static_cast<double>(std::abs(mean_square(t.v) - start) / start);
    if (!(drift <= 1e-11)) {
      ADD_FAILURE() << explain(text("<v^2> to stay constant (relative drift below 1e-11) over ", kLongRunEvents,
                                    " collisions in ", t.label),
                               text("after collision ", e, " (", describe(got, t), ") it drifted by ", drift, " relative"),
                               "a bounce off a wall keeps the speed only if the normal is a unit vector: at a face "
                               "n = perpendicular of (b - a) / |b - a|, at an end point n = (r - p) / |r - p|, and "
                               "v' = v - 2 (v.n) n.");
      return;
    }
  }
}

GRADED_TEST(Walls, LongRunKeepsCirclesApartOnTheTableAndOffTheWalls, 3, after_due_date) {
  WallTable t = long_run_table();
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text(t.label, ", collision ", e))) return;
    int i = -1, j = -1, w = -1;
    const double overlap = billiard::testing::worst_overlap(t.c, t.a, &i, &j);
    const double protrusion = billiard::testing::worst_protrusion(t.c, t.R, t.a, &w);
    if (!(overlap <= 1e-9) || !(protrusion <= 1e-9)) {
      ADD_FAILURE() << explain("no two circles to overlap and every circle to stay on the table (within 1e-9)",
                               text("after collision ", e, " (", describe(got, t), ") ",
                                    overlap > 1e-9 ? text("circles ", i, " and ", j, " overlap by ", overlap)
                                                   : text("circle ", w, " sticks out by ", protrusion)),
                               kHintEarliest);
      return;
    }
    for (int c = 0; c < t.n(); ++c) {
      for (std::size_t k = 0; k < t.walls.size(); ++k) {
        const double distance = billiard::testing::segment_distance(t.c.row(c), t.walls[k]);
        if (!(distance >= t.a - 1e-9)) {
          ADD_FAILURE() << explain(
              "every circle's centre to stay at least circle_radius (less 1e-9) from every wall",
              text("after collision ", e, " (", describe(got, t), ") circle ", c, " at ", row(t.c, c), " is ",
                   distance, " from walls[", k, "] (circle_radius ", t.a, ")"),
              "a circle overlapping a wall missed a hit: check both faces (either sign of d0), the foot between a and "
              "b, both end points of every wall, and accept t = 0 for a touching circle moving towards a wall.");
          return;
        }
      }
    }
  }
}

GRADED_TEST(Walls, NoCircleCrossesAWallSpanningTheTable, 2, after_due_date) {
  // walls[0] of the long run is a chord from rim to rim: no circle can ever change sides.
  WallTable t = long_run_table();
  std::vector<double> side(static_cast<std::size_t>(t.n()));
  for (int c = 0; c < t.n(); ++c) side[static_cast<std::size_t>(c)] = billiard::testing::side_of(t.c.row(c), t.walls[0]);
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text(t.label, ", collision ", e))) return;
    for (int c = 0; c < t.n(); ++c) {
      if (!(billiard::testing::side_of(t.c.row(c), t.walls[0]) * side[static_cast<std::size_t>(c)] > 0)) {
        ADD_FAILURE() << explain("every circle to stay on its side of walls[0], a wall across the whole table",
                                 text("after collision ", e, " (", describe(got, t), ") circle ", c, " is at ",
                                      row(t.c, c), ", on the other side"),
                                 text("a circle passed through a face: ", kHintBothFaces));
        return;
      }
    }
  }
}

GRADED_TEST(Walls, NoCircleEscapesAClosedTriangleOfWalls, 2, after_due_date) {
  // Three walls sharing their corners: circles inside stay inside, those outside stay out,
  // also at the corners where two walls meet.
  WallTable t = triangle_table(8, 8, 71);
  auto inside = [&t](const Vector& p) {
    return billiard::testing::side_of(p, t.walls[0]) > 0 && billiard::testing::side_of(p, t.walls[1]) > 0 &&
           billiard::testing::side_of(p, t.walls[2]) > 0;
  };
  std::vector<bool> was_inside;
  for (int c = 0; c < t.n(); ++c) was_inside.push_back(inside(t.c.row(c)));
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text(t.label, ", collision ", e))) return;
    for (int c = 0; c < t.n(); ++c) {
      if (inside(t.c.row(c)) != was_inside[static_cast<std::size_t>(c)]) {
        ADD_FAILURE() << explain(text("circle ", c, " to stay ", was_inside[static_cast<std::size_t>(c)] ? "inside" : "outside",
                                      " a closed triangle of walls"),
                                 text("after collision ", e, " (", describe(got, t), ") it is at ", row(t.c, c)),
                                 "where two walls meet, a circle reaching the corner touches their faces or the "
                                 "shared end point; test both faces of every wall and both end points.");
        return;
      }
    }
  }
}

GRADED_TEST(Walls, ReportsValidIdsAndNeverRepeatsAWallHitAtOnce, 2, after_due_date) {
  // 20 random tables, 300 steps each: `circle` a row, `other` kWall, wall_id(k) of an existing
  // wall or another circle; and never the same circle with the same wall twice in a row at a
  // time below 1e-9 of R / |v| (a true repeat needs time to come back).
  for (int k = 0; k < 20; ++k) {
    WallTable t = billiard::testing::random_wall_table(k, 99);
    const int n = t.n();
    const int walls = static_cast<int>(t.walls.size());
    const double scale = t.R / std::sqrt(t.v.squaredNorm());
    Collision previous{-1, -1, 0};
    for (int e = 0; e < 300; ++e) {
      Collision got{};
      if (!checked_step(t, got, text(t.label, ", step ", e))) return;
      const bool circle_ok = got.circle >= 0 && got.circle < n;
      const bool other_ok = got.other == kWall || (got.other <= -2 && got.other >= wall_id(walls - 1)) ||
                            (got.other >= 0 && got.other < n && got.other != got.circle);
      if (!circle_ok || !other_ok) {
        ADD_FAILURE() << explain(text("`circle` a row 0..", n - 1, " and `other` kWall, wall_id(0..", walls - 1,
                                      ") or another circle's row (", t.label, ", step ", e, ")"),
                                 text("returned ", describe(got, t)), kHintWallId);
        return;
      }
      if (got.other <= -2 && got.circle == previous.circle && got.other == previous.other && got.time <= 1e-9 * scale) {
        ADD_FAILURE() << explain(text("a different event after ", describe(previous, t), " (", t.label, ", step ", e, ")"),
                                 text("returned the same wall hit again: ", describe(got, t)), kHintApproach);
        return;
      }
      previous = got;
    }
  }
}

GRADED_TEST(Walls, LongRunTimesAreFiniteAndNotNegative, 2, after_due_date) {
  WallTable t = long_run_table();
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text(t.label, ", collision ", e))) return;
    if (!(std::isfinite(got.time) && got.time >= 0)) {
      ADD_FAILURE() << explain("every returned time to be finite and >= 0", text("collision ", e, " returned ", describe(got, t)),
                               "take only times of approaching contacts, clamp tiny negative ones to 0, and skip "
                               "events that never happen (infinite or NaN) when looking for the earliest.");
      return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 6. Invalid input: std::invalid_argument naming the argument, and the state left unchanged.

using billiard::testing::expect_invalid_argument;

// One circle at the origin moving (1, 0), a wall along y = 4, and what is to be broken.
WallTable valid_table() { return one_circle(0, 0, 1, 0, {wall(-5, 4, 5, 4)}); }

// Calls propagate_walls on `t` expecting std::invalid_argument naming `argument`, and checks
// that coordinates and velocities are unchanged afterwards.
void expect_rejected(WallTable t, const std::string& situation, const std::string& argument, const std::string& hint) {
  const Coordinates c = t.c;
  const Velocities v = t.v;
  expect_invalid_argument([&] { billiard::propagate_walls(t.R, t.a, t.n(), t.c, t.v, t.walls); }, situation, argument,
                          hint);
  if (t.c.rows() == c.rows() && t.v.rows() == v.rows()) {
    EXPECT_TRUE(t.c == c && t.v == v) << explain(text("coordinates and velocities unchanged after the error for ", situation),
                                                 "they were changed",
                                                 "check every argument before moving anything (all checks:: calls first).");
  }
}

GRADED_TEST(Walls, RejectsWallEndOutsideTheTable, 1, after_due_date) {
  for (const Wall& w : {wall(-5, 4, 11, 4), wall(0, 12, 0, 11), wall(8, 8, 0, 0)}) {
    WallTable t = valid_table();
    t.walls.push_back(w);
    expect_rejected(t, text("a wall from (", w.a(0), ", ", w.a(1), ") to (", w.b(0), ", ", w.b(1), ") on a table of radius 10"), "walls",
                    "a wall's end points must lie in the table: call checks::walls(table_radius, walls).");
  }
}

GRADED_TEST(Walls, RejectsNonFiniteWallEnd, 1, after_due_date) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Wall& w : {wall(nan, 0, 1, 1), wall(0, 0, 1, inf)}) {
    WallTable t = valid_table();
    t.walls.push_back(w);
    expect_rejected(t, "a wall with a NaN or infinite end point", "walls",
                    "NaN fails every comparison: call checks::walls(table_radius, walls), which tests finiteness.");
  }
}

GRADED_TEST(Walls, RejectsCircleOverlappingAWall, 1, after_due_date) {
  // Centres 0.5 from the wall's face, and 0.54 from its end point (5, 4): closer than a = 1.
  for (const Vector& p : {Vector(0, 3.5), Vector(5.5, 4.2)}) {
    WallTable t = one_circle(p(0), p(1), 1, 0, {wall(-5, 4, 5, 4)});
    expect_rejected(t, text("a circle at (", p(0), ", ", p(1), ") overlapping a wall along y = 4 from x = -5 to 5"), "coordinates",
                    "call checks::clear_of_walls(table_radius, circle_radius, coordinates, walls) before moving.");
  }
}

GRADED_TEST(Walls, RejectsNoCirclesOrAllAtRest, 1, after_due_date) {
  WallTable empty = valid_table();
  empty.c = Coordinates(0, 2);
  empty.v = Velocities(0, 2);
  expect_rejected(empty, "n = 0 (no circle, so no collision ever)", "",
                  "with no circles there is no earliest collision: throw std::invalid_argument.");
  WallTable resting = valid_table();
  resting.v.setZero();
  expect_rejected(resting, "all circles at rest (no collision ever)", "",
                  "if no event has a finite time, throw std::invalid_argument instead of moving by infinity.");
}

GRADED_TEST(Walls, RejectsBadRadiiAndRowCounts, 1, after_due_date) {
  WallTable t = valid_table();
  t.R = -10;
  expect_rejected(t, "table_radius = -10", "table_radius", "call checks::table(table_radius, circle_radius, n).");
  t = valid_table();
  t.a = std::numeric_limits<double>::quiet_NaN();
  expect_rejected(t, "circle_radius = NaN", "circle_radius", "call checks::table(table_radius, circle_radius, n).");
  t = valid_table();
  Velocities two(2, 2);
  two << 1, 0, -1, 0;
  expect_invalid_argument([&] { billiard::propagate_walls(t.R, t.a, 1, t.c, two, t.walls); },
                          "velocities with 2 rows for n = 1", "velocities",
                          "call checks::rows(velocities, n, \"velocities\").");
  Coordinates three(3, 2);
  three << -5, 0, 5, 0, 0, -5;
  expect_invalid_argument([&] { billiard::propagate_walls(t.R, t.a, 1, three, t.v, t.walls); },
                          "coordinates with 3 rows for n = 1", "coordinates",
                          "call checks::rows(coordinates, n, \"coordinates\").");
}

GRADED_TEST(Walls, RejectsCirclesOffTheTableOrOverlapping, 1, after_due_date) {
  WallTable t = valid_table();
  t.c << 9.5, 0;  // sticks out of the table by 0.5
  expect_rejected(t, "a circle at (9.5, 0) sticking out of a table of radius 10", "coordinates",
                  "call checks::placement(table_radius, circle_radius, coordinates).");
  WallTable two = valid_table();
  two.c = Coordinates(2, 2);
  two.v = Velocities(2, 2);
  two.c << 0, 0, 1, 0;  // centres 1 apart, radius 1
  two.v << 1, 0, -1, 0;
  expect_rejected(two, "two overlapping circles", "coordinates",
                  "call checks::placement(table_radius, circle_radius, coordinates).");
}

}  // namespace
