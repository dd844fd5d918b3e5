// Graded tests of task 7, `propagate_gravity` and `mean_energy`: one event step of hard circles
// on a circular table under a uniform gravity g, and the energy that step conserves.
//
// What is checked, and how (never one implementation, always the physics):
//   - hand-solved cases: a circle dropped from rest, a sideways throw whose quartic has the
//     root t = 4, the same throw for g in other directions, a falling pair;
//   - the traps of the quartic wall time: no second hit right after a bounce, an outward-moving
//     circle on the wall bounces at once, an arc that leaves the table for only 3e-4 time units;
//   - wall times of random single arcs against the library's quartic solver
//     (billiard::disc_in_circle_time), which has no contact slack;
//   - g = 0: exactly task 4, against the independent propagate oracle (support/oracle.hpp);
//   - conservation of the energy per circle and no overlap or escape over 2000 events;
//   - every step from many random shared states against the finished library
//     (billiard::Simulation), one step at a time, because the dynamics is chaotic: rounding
//     differences grow by ~1e10 over 1000 events, so long trajectories never agree;
//   - mean_energy by hand, and the argument checks (naming the argument, state unchanged).
// Tolerances: hand cases have numbers of order 1 to 20 and the roots are found to full double
// precision (~1e-15), so 1e-12 is allowed there and 1e-9 where many steps add up or the
// comparison is with another implementation. The library meets the wall 1e-10 radii beyond
// touching under gravity; the comparison with it allows for that (see gravity_support.hpp).
#include "gravity_support.hpp"

#include "time_of_impact.hpp"
#include "billiard/extensions.hpp"
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// A failing test draws the step that went wrong (support/failure_pictures.hpp).
const bool kPicturesJudged = billiard::testing::register_step_judge("propagate_gravity", billiard::testing::gravity_judgement);

using billiard::Collision;
using billiard::Coordinates;
using billiard::kWall;
using billiard::Vector;
using billiard::Velocities;
using billiard::testing::describe_collision;
using billiard::testing::explain;
using billiard::testing::GravityTable;
using billiard::testing::row;
using billiard::testing::text;

using Table = GravityTable;

constexpr double kTol = 1e-12;
const double kSqrt18 = std::sqrt(18.0);

const char* const kHintWallQuartic =
    "under gravity the centre moves on r + v t + g t^2/2, so the wall time is the first upward crossing of the "
    "quartic f(t) = |r + v t + g t^2/2|^2 - (R - a)^2 (coefficients in tasks/gravity.cpp); the straight-line "
    "quadratic of propagate is right only for g = 0.";
const char* const kHintEvenFromRest =
    "under gravity every circle reaches the wall sooner or later, even from rest: solve the quartic "
    "|r + v t + g t^2/2| = R - a for the wall time instead of propagate's quadratic, which has no root when v = 0. "
    "Only n = 0, or g = 0 with all circles at rest, has no next event.";
const char* const kHintZeroGravity =
    "with g = 0 the quartic degenerates (its t^4 and t^3 coefficients vanish and the bound t_max is infinite): "
    "use propagate's quadratic for the wall time when g = 0, so that the stage then behaves exactly like propagate.";
const char* const kHintParabola =
    "every circle moves on its parabola during the step: r += v t + g t^2/2 (do not forget the g t^2/2 term), "
    "and v += g t, the circles that do not collide included.";
const char* const kHintVelocityGain =
    "every velocity changes during the step: v += g t for every circle, before the collision is processed.";
const char* const kHintContactVelocity =
    "reflect the velocity the circle has at the moment of contact, v + g t: first add g t to every velocity, "
    "then v' = v - 2 (v.n) n with n = r / |r| at the contact point.";
const char* const kHintPairTime =
    "gravity cancels in the relative motion of two circles (both fall alike): the pair time is exactly the one "
    "of propagate, from dr = r_i - r_j and dv = v_i - v_j, with no g in it.";
const char* const kHintPairVelocity =
    "exchange only the velocity components along the line of centres, n = (r_j - r_i) / |r_j - r_i|, using the "
    "velocities at contact (v + g t), as in propagate.";
const char* const kHintNoRepeat =
    "right after a wall bounce the circle sits on the wall (f(0) ~ 0, perhaps a hair positive by rounding) and "
    "moves inward: that root at t ~ 0 is no hit. Count only upward crossings of f(t) = |r(t)|^2 - (R - a)^2, "
    "where the circle moves outward, not the smallest positive root.";
const char* const kHintOutwardNow =
    "a circle on or a hair outside the wall (rounding) that moves outward (r.v > 0) must bounce at once, at "
    "time 0; otherwise it leaves the table before the next crossing is found.";
const char* const kHintCloseRoots =
    "an arc that grazes the wall has two close roots (it is outside only between them); split [0, t_max] at the "
    "roots of f' so that each monotone piece is checked, and bisect the first piece where f goes from < 0 to "
    ">= 0. Sampling f at fixed steps steps over the short time outside.";
const char* const kHintEarliest =
    "compute every circle's wall time (the first upward crossing of the quartic) and every approaching pair's "
    "contact time (as in propagate, no g), and return the smallest.";
const char* const kHintRecollision =
    "a pair that has just collided touches (c ~ 0) but moves apart (b = dr.dv > 0): only approaching pairs "
    "(b < 0) can collide, as in propagate; gravity changes nothing there.";

Table make_table(double R, double a, int n, double gx, double gy) {
  Table t;
  t.R = R;
  t.a = a;
  t.c = Coordinates::Zero(n, 2);
  t.v = Velocities::Zero(n, 2);
  t.g << gx, gy;
  return t;
}

// A failing mean_energy test draws its circles, their velocities and g.
void draw_if_failing(const Coordinates& c, const Velocities& v, const Vector& g) {
  billiard::testing::set_case_source([c, v, g] {
    billiard::testing::Board board = billiard::testing::table_board(0, 0, {}, g);
    board.coordinates = c;
    board.velocities = v;
    return billiard::testing::state_case(board, "The circles mean_energy was given (velocities as arrows, g top left)");
  });
}

std::string vec(const Vector& x) { return text("(", x(0), ", ", x(1), ")"); }

// Calls the student's propagate_gravity. A negative time and a circle paired with itself are
// wrong in every test; they are reported here first.
Collision step(Table& t) {
  const Collision got = billiard::testing::recorded_gravity_step(t.R, t.a, t.n(), t.c, t.v, t.g);
  if (got.time < 0) {
    ADD_FAILURE() << explain("the time until the next collision, which is never negative",
                             text("returned ", describe_collision(got)),
                             "a negative time is an event in the past: take only upward crossings of the wall quartic "
                             "at t >= 0 and, for pairs, only approaching ones (b < 0), clamped to 0.");
  }
  if (got.other == got.circle) {
    ADD_FAILURE() << explain("a collision of two different circles, or of a circle with the wall",
                             text("returned ", describe_collision(got)),
                             "loop over pairs j > i: a circle cannot collide with itself.");
  }
  return got;
}

// step(), turning an std::invalid_argument on a valid state into a failure with a hint.
bool checked_step(Table& t, Collision& got, const std::string& where) {
  try {
    got = step(t);
    return true;
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(text("propagate_gravity to accept a valid state and find its next collision (", where,
                                  ", g = ", vec(t.g), ")"),
                             text("it threw std::invalid_argument: \"", error.what(), "\""),
                             t.g.isZero(0) ? kHintZeroGravity : kHintEvenFromRest);
    return false;
  }
}

bool is_wall(const Collision& c, int i) { return c.circle == i && c.other == kWall; }
bool is_pair(const Collision& c, int i, int j) {
  return (c.circle == i && c.other == j) || (c.circle == j && c.other == i);
}

void expect_row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int i, const Vector& expected, double tolerance,
                const std::string& what, const std::string& hint) {
  const double error = (rows.row(i) - expected).norm();
  EXPECT_LE(error, tolerance) << explain(text(what, " to be ", vec(expected), " (within ", tolerance, ")"),
                                         text("it is ", row(rows, i)), hint);
}

// The velocity check after a wall hit, with a hint chosen by what the velocity looks like: not
// changed by g t at all, or reflected before g t was added.
void expect_wall_velocity(const Table& before, const Table& after, int i, const Vector& expected,
                          const std::string& what) {
  const Vector got = after.v.row(i);
  const Vector v0 = before.v.row(i);
  const Vector normal = after.c.row(i).normalized();
  const Vector no_gain = v0 - 2 * v0.dot(normal) * normal;
  const double tolerance = 1e-9 * (1 + expected.norm());
  const char* hint = kHintContactVelocity;
  if ((got - no_gain).norm() <= tolerance && (got - expected).norm() > tolerance) hint = kHintVelocityGain;
  expect_row(after.v, i, expected, tolerance, what, hint);
}

// ---------------------------------------------------------------------------------------------
// 1. Hand-solved cases (visible).

GRADED_TEST(Gravity, CircleDroppedFromRestFallsToTheWall, 2, visible) {
  // R = 10, a = 1, g = (0, -1): from rest at the centre the circle falls 9 in t^2 / 2 = 9,
  // t = sqrt(18), arriving at (0, -9) with velocity (0, -sqrt(18)); the wall sends it back up
  // at (0, sqrt(18)). Without gravity it would never move: a next event exists only with g.
  Table t = make_table(10, 1, 1, 0, -1);
  const Table before = t;
  Collision got{};
  if (!checked_step(t, got, "a circle at rest at the centre")) return;
  ASSERT_TRUE(is_wall(got, 0)) << explain("circle 0 to hit the wall", text("returned ", describe_collision(got)),
                                          kHintWallQuartic);
  EXPECT_NEAR(got.time, kSqrt18, kTol) << explain(
      text("the circle to fall for t = sqrt(18) = ", kSqrt18, " (it falls 9 = t^2 / 2)"),
      text("returned ", describe_collision(got)), kHintWallQuartic);
  expect_row(t.c, 0, Vector(0, -9), kTol, "the point where the circle reaches the wall", kHintParabola);
  expect_wall_velocity(before, t, 0, Vector(0, kSqrt18), "the velocity after the bounce");
}

GRADED_TEST(Gravity, FallingPairCollidesAsWithoutGravity, 2, visible) {
  // Two circles 10 apart closing at speed 2 touch after time 4, whatever g: both fall 8 in that
  // time. At contact, (-1, -8) and (1, -8) with velocities (1, -4) and (-1, -4); the head-on
  // collision swaps the x components: (-1, -4) and (1, -4).
  Table t = make_table(20, 1, 2, 0, -1);
  t.c << -5, 0, 5, 0;
  t.v << 1, 0, -1, 0;
  Collision got{};
  if (!checked_step(t, got, "two circles closing head-on while falling")) return;
  ASSERT_TRUE(is_pair(got, 0, 1)) << explain("circles 0 and 1 to collide", text("returned ", describe_collision(got)),
                                             kHintPairTime);
  EXPECT_NEAR(got.time, 4, kTol) << explain("the collision time 4, the same as without gravity",
                                            text("returned ", describe_collision(got)), kHintPairTime);
  expect_row(t.c, 0, Vector(-1, -8), kTol, "circle 0's position at the collision", kHintParabola);
  expect_row(t.c, 1, Vector(1, -8), kTol, "circle 1's position at the collision", kHintParabola);
  expect_row(t.v, 0, Vector(-1, -4), kTol, "circle 0's velocity after the collision", kHintPairVelocity);
  expect_row(t.v, 1, Vector(1, -4), kTol, "circle 1's velocity after the collision", kHintPairVelocity);
}

// The sideways throw: from the centre with v = (3, 0) under g = (0, -2) the centre is at
// (3t, -t^2), so |r|^2 = 9 t^2 + t^4, which is 400 = 20^2 at t = 4 (144 + 256). On a table
// R = 21 with a = 1 the circle reaches the wall at (12, -16) with velocity (3, -8); there
// n = (0.6, -0.8), v.n = 8.2 and v' = (3, -8) - 16.4 n = (-6.84, 5.12).
void check_throw(double angle, const std::string& label) {
  const double c = std::cos(angle), s = std::sin(angle);
  auto turn = [&](double x, double y) { return Vector(c * x - s * y, s * x + c * y); };
  Table t = make_table(21, 1, 1, 0, 0);
  t.g = turn(0, -2);
  t.v.row(0) = turn(3, 0);
  const Table before = t;
  Collision got{};
  if (!checked_step(t, got, label)) return;
  ASSERT_TRUE(is_wall(got, 0)) << explain(text("circle 0 to hit the wall (", label, ")"),
                                          text("returned ", describe_collision(got)), kHintWallQuartic);
  EXPECT_NEAR(got.time, 4, kTol) << explain(text("the wall time 4, the root of 9 t^2 + t^4 = 400 (", label, ")"),
                                            text("returned ", describe_collision(got)), kHintWallQuartic);
  expect_row(t.c, 0, turn(12, -16), kTol, text("the contact point (", label, ")"), kHintParabola);
  expect_wall_velocity(before, t, 0, turn(-6.84, 5.12), text("the velocity after the bounce (", label, ")"));
}

GRADED_TEST(Gravity, CircleThrownSidewaysHitsTheWallAtTimeFour, 3, visible) {
  check_throw(0, "thrown from the centre with v = (3, 0), g = (0, -2), R = 21, a = 1");
}

// mean_energy by hand: E = (1/n) sum (|v|^2 / 2 - g.r).
GRADED_TEST(Gravity, MeanEnergyPotentialGrowsAgainstGravity, 1, visible) {
  struct Case {
    double x, y, vx, vy, gx, gy, expected;
    const char* what;
  };
  const Case cases[] = {
      {2, 3, 0, 0, 0, -1, 3, "a circle at rest at height 3 under g = (0, -1): potential energy -g.r = 3"},
      {2, 3, 0, 0, 0.5, 0, -1, "a circle at rest at (2, 3) under g = (0.5, 0): it is 'below' by 2, -g.r = -1"},
      {0, 0, 3, 4, 0, -1, 12.5, "a circle at the centre with velocity (3, 4): kinetic energy |v|^2 / 2 = 12.5"},
      {1, -2, 1, 1, 0, -2, -3, "a circle at (1, -2) with velocity (1, 1) under g = (0, -2): 1 - 4 = -3"}};
  for (const Case& k : cases) {
    Coordinates c(1, 2);
    Velocities v(1, 2);
    c << k.x, k.y;
    v << k.vx, k.vy;
    draw_if_failing(c, v, Vector(k.gx, k.gy));
    const double got = billiard::mean_energy(1, c, v, Vector(k.gx, k.gy));
    const double flipped = (k.vx * k.vx + k.vy * k.vy) / 2 + (k.gx * k.x + k.gy * k.y);
    const double no_half = k.vx * k.vx + k.vy * k.vy - (k.gx * k.x + k.gy * k.y);
    const char* hint = "mean_energy = (1/n) sum_i (|v_i|^2 / 2 - g.r_i).";
    if (std::abs(got - flipped) <= kTol && std::abs(flipped - k.expected) > kTol) {
      hint = "the potential energy is -g.r: it grows against gravity (with g = (0, -1) a circle at height y has "
             "potential energy y, the familiar m g h), so the sign of g.r is minus.";
    } else if (std::abs(got - no_half) <= kTol && std::abs(no_half - k.expected) > kTol) {
      hint = "the kinetic energy of a unit mass is |v|^2 / 2, with the half.";
    }
    EXPECT_NEAR(got, k.expected, kTol) << explain(text(k.what, ": mean_energy = ", k.expected),
                                                  text("returned ", got), hint);
  }
}

GRADED_TEST(Gravity, MeanEnergyIsAMeanOverCircles, 1, visible) {
  // Circle 0: |(3, 4)|^2 / 2 - (0, -2).(1, 2) = 12.5 + 4; circle 1 at rest at (0, -3): -6.
  // The mean of 16.5 and -6 is 5.25.
  Coordinates c(2, 2);
  Velocities v(2, 2);
  c << 1, 2, 0, -3;
  v << 3, 4, 0, 0;
  draw_if_failing(c, v, Vector(0, -2));
  const double got = billiard::mean_energy(2, c, v, Vector(0, -2));
  EXPECT_NEAR(got, 5.25, kTol) << explain(
      "mean_energy = (16.5 + (-6)) / 2 = 5.25 for two circles", text("returned ", got),
      std::abs(got - 10.5) <= kTol ? "mean_energy is a mean per circle, not a total: divide the sum by n, so that "
                                     "tables with different n compare."
                                   : "mean_energy = (1/n) sum_i (|v_i|^2 / 2 - g.r_i), summed over all n circles.");
}

// ---------------------------------------------------------------------------------------------
// 2. The wall under gravity: any direction, repeated bounces, and the traps of the quartic.

GRADED_TEST(Gravity, ThrowWorksForGravityInAnyDirection, 2, after_due_date) {
  // The sideways throw turned by eight angles: only the direction of g differs, so times stay 4
  // and the points and velocities turn with it.
  for (int k = 0; k < 8; ++k) {
    const double angle = 0.3 + k * std::acos(-1.0) / 4;
    check_throw(angle, text("the sideways throw turned by ", angle, " rad"));
    if (HasFailure()) return;
  }
}

GRADED_TEST(Gravity, DroppedCircleBouncesBackEveryTwiceTheFallTime, 2, visible) {
  // After the first bounce at t = sqrt(18) the circle flies straight up, stops at the centre
  // and falls back: it hits the wall again every 2 sqrt(18), always at (0, -9), leaving with
  // (0, sqrt(18)). Rounding of 1e-15 per bounce; 1e-9 allows for ten of them.
  Table t = make_table(10, 1, 1, 0, -1);
  Collision got{};
  if (!checked_step(t, got, "the first fall")) return;
  for (int bounce = 1; bounce <= 10; ++bounce) {
    if (!checked_step(t, got, text("bounce ", bounce))) return;
    if (!is_wall(got, 0) || !(std::abs(got.time - 2 * kSqrt18) <= 1e-9)) {
      ADD_FAILURE() << explain(
          text("after bounce ", bounce, " the next wall hit after 2 sqrt(18) = ", 2 * kSqrt18,
               " (up to the centre and back)"),
          text("returned ", describe_collision(got)), got.time < 1e-6 ? kHintNoRepeat : kHintWallQuartic);
      return;
    }
    expect_row(t.c, 0, Vector(0, -9), 1e-9, text("the contact point at bounce ", bounce), kHintParabola);
    expect_row(t.v, 0, Vector(0, kSqrt18), 1e-9, text("the velocity after bounce ", bounce), kHintContactVelocity);
    if (HasFailure()) return;
  }
}

GRADED_TEST(Gravity, CircleThatJustBouncedDoesNotHitTheWallAgain, 3, after_due_date) {
  // Circles a hair outside the wall (1e-15 relative, as rounding leaves them after a bounce),
  // moving inward: the next wall hit is a whole arc later. The expected times come from the
  // library's quartic solver (billiard::disc_in_circle_time); the first is the vertical case,
  // 6 = 2 * 3 / 1 (up at speed 3 and back).
  struct Case {
    double angle, vx, vy, gx, gy;
  };
  const Case cases[] = {{0, 0, 3, 0, -1}, {0.4, 0.7, 2.5, 0, -1}, {-1.1, 1, 1.5, 0.3, -2}, {2.5, -1.2, -0.4, 1, 0.2}};
  for (const Case& k : cases) {
    const double scale = 9 * (1 + 1e-15);
    Table t = make_table(10, 1, 1, k.gx, k.gy);
    t.c << scale * std::sin(k.angle), -scale * std::cos(k.angle);
    t.v << k.vx, k.vy;
    ASSERT_LT(t.c.row(0).dot(t.v.row(0)), 0) << "test case error: the circle must move inward";
    const double expected = billiard::disc_in_circle_time(t.c.row(0), t.v.row(0),
                                                          t.g, 9);
    ASSERT_GT(expected, 0.1) << "test case error: the reference time must be a whole arc";
    const std::string label = text("a circle at ", row(t.c, 0), " (on the wall) moving inward with ", row(t.v, 0),
                                   ", g = ", vec(t.g));
    Collision got{};
    if (!checked_step(t, got, label)) return;
    EXPECT_TRUE(is_wall(got, 0) && std::abs(got.time - expected) <= 1e-9)
        << explain(text(label, ": the next wall hit after time ", expected), text("returned ", describe_collision(got)),
                   got.time < 1e-6 ? kHintNoRepeat : kHintWallQuartic);
    if (HasFailure()) return;
  }
}

GRADED_TEST(Gravity, CircleOnTheWallMovingOutwardBouncesAtOnce, 2, visible) {
  // At the top of the table, (0, 9), moving (0.5, 1): outward. It must bounce now (t = 0) with
  // v' = (0.5, -1). Were it let go, it would fly out and come back only later.
  Table t = make_table(10, 1, 1, 0, -1);
  t.c << 0, 9;
  t.v << 0.5, 1;
  Collision got{};
  if (!checked_step(t, got, "a circle on the wall moving outward")) return;
  EXPECT_TRUE(is_wall(got, 0) && got.time <= kTol)
      << explain("a circle at (0, 9) on the wall (R = 10, a = 1) moving outward with (0.5, 1) to bounce at time 0",
                 text("returned ", describe_collision(got)), kHintOutwardNow);
  expect_row(t.v, 0, Vector(0.5, -1), kTol, "the velocity after that bounce", kHintOutwardNow);
  // The same a hair outside (rounding) on the side, under sideways gravity.
  Table side = make_table(10, 1, 1, 1, 0);
  side.c << -9 * (1 + 1e-15), 0;
  side.v << -0.25, 2;
  if (!checked_step(side, got, "a circle a hair outside the wall moving outward")) return;
  EXPECT_TRUE(is_wall(got, 0) && got.time <= kTol)
      << explain("a circle at (-9 - 1e-14, 0) (outside by rounding) moving outward with (-0.25, 2) to bounce at "
                 "time 0",
                 text("returned ", describe_collision(got)), kHintOutwardNow);
  expect_row(side.v, 0, Vector(0.25, 2), 1e-9, "the velocity after that bounce", kHintOutwardNow);
}

// A near-grazing arc: thrown from (-3, 4.5 + eps) with v = (1, 3) under g = (0, -1) on a table
// R = 10, a = 1 (reach 9), the apex at t = 3 is (0, 9 + eps): the circle is outside only for
// |t - 3| < 1.5 sqrt(eps). Around the apex, with s = t - 3, |r|^2 - 81 = s^4/4 - (8 + eps) s^2 +
// 18 eps + eps^2, a quadratic in u = s^2 whose small root is u = 2c / (B + sqrt(B^2 - c)) with
// B = 8 + eps and c = 18 eps + eps^2: the first hit is at t = 3 - sqrt(u). Missed, the circle
// would fly on and hit the wall only near t = 8.66.
GRADED_TEST(Gravity, GrazingArcHitsAtTheFirstOfTwoCloseRoots, 3, visible) {
  for (const double angle : {0.0, 0.7, -2.0}) {
    const double c = std::cos(angle), s = std::sin(angle);
    auto turn = [&](double x, double y) { return Vector(c * x - s * y, s * x + c * y); };
    const double y0 = 4.5 + 1e-8;
    const long double eps = (static_cast<long double>(y0) + 4.5L) - 9;  // the eps the double y0 really gives
    const long double B = 8 + eps, C = 18 * eps + eps * eps;
    const double expected = static_cast<double>(3 - std::sqrt(2 * C / (B + std::sqrt(B * B - C))));
    Table t = make_table(10, 1, 1, 0, 0);
    t.c.row(0) = turn(-3, y0);
    t.v.row(0) = turn(1, 3);
    t.g = turn(0, -1);
    const std::string label = text("a circle from ", row(t.c, 0), " with velocity ", row(t.v, 0), " under g = ",
                                   vec(t.g), ", outside the wall only between t = ", expected, " and ",
                                   6 - expected);
    Collision got{};
    if (!checked_step(t, got, label)) return;
    EXPECT_TRUE(is_wall(got, 0) && std::abs(got.time - expected) <= 1e-9)
        << explain(text(label, ": the wall hit at t = ", expected), text("returned ", describe_collision(got)),
                   kHintCloseRoots);
    if (HasFailure()) return;
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Everything falls; pairs as in propagate.

GRADED_TEST(Gravity, EveryCircleFollowsItsParabolaDuringTheStep, 2, after_due_date) {
  // The falling pair of FallingPairCollidesAsWithoutGravity collides at t = 4; bystander 2 at
  // rest at (0, 8) falls to (0, 0) and gains (0, -4); bystander 3 from (-8, 5) with (0.5, 1)
  // moves to (-8 + 2, 5 + 4 - 8) = (-6, 1) with velocity (0.5, -3).
  Table t = make_table(20, 1, 4, 0, -1);
  t.c << -5, 0, 5, 0, 0, 8, -8, 5;
  t.v << 1, 0, -1, 0, 0, 0, 0.5, 1;
  Collision got{};
  if (!checked_step(t, got, "a falling pair with two bystanders")) return;
  ASSERT_TRUE(is_pair(got, 0, 1) && std::abs(got.time - 4) <= kTol)
      << explain("circles 0 and 1 to collide at time 4", text("returned ", describe_collision(got)), kHintEarliest);
  expect_row(t.c, 2, Vector(0, 0), kTol, "bystander 2 (at rest at (0, 8)) after falling for time 4", kHintParabola);
  expect_row(t.c, 3, Vector(-6, 1), kTol, "bystander 3 (from (-8, 5) with (0.5, 1)) after time 4", kHintParabola);
  expect_row(t.v, 2, Vector(0, -4), kTol, "bystander 2's velocity after time 4", kHintVelocityGain);
  expect_row(t.v, 3, Vector(0.5, -3), kTol, "bystander 3's velocity after time 4", kHintVelocityGain);
}

GRADED_TEST(Gravity, ObliquePairCollisionUsesVelocitiesAtContact, 2, after_due_date) {
  // Circle 0 from (-4, 1) with (1, 0) hits circle 1 at rest at the origin; both fall alike, so
  // contact is at t = 4 - sqrt(3) as without gravity, along n = (sqrt(3), -1) / 2. The
  // velocities at contact are (1, -t) and (0, -t); the exchange along n gives
  // (1/4, sqrt(3)/4 - t) and (3/4, -sqrt(3)/4 - t).
  const double s3 = std::sqrt(3.0);
  const double tc = 4 - s3;
  Table t = make_table(20, 1, 2, 0, -1);
  t.c << -4, 1, 0, 0;
  t.v << 1, 0, 0, 0;
  Collision got{};
  if (!checked_step(t, got, "an off-centre hit of a resting circle while falling")) return;
  ASSERT_TRUE(is_pair(got, 0, 1)) << explain("circles 0 and 1 to collide", text("returned ", describe_collision(got)),
                                             kHintPairTime);
  EXPECT_NEAR(got.time, tc, kTol) << explain(text("the contact time 4 - sqrt(3) = ", tc),
                                             text("returned ", describe_collision(got)), kHintPairTime);
  expect_row(t.c, 0, Vector(-s3, 1 - tc * tc / 2), kTol, "circle 0 at contact", kHintParabola);
  expect_row(t.v, 0, Vector(0.25, s3 / 4 - tc), kTol, "circle 0's velocity after the hit", kHintPairVelocity);
  expect_row(t.v, 1, Vector(0.75, -s3 / 4 - tc), kTol, "circle 1's velocity after the hit", kHintPairVelocity);
}

GRADED_TEST(Gravity, EarliestOfWallAndPairEventsIsChosen, 2, after_due_date) {
  // A pair at (-5, 2), (5, 2) closing at speed 2 meets at t = 4. Circle 2 at rest at (0, -7)
  // reaches the wall (reach 9) after falling 2: t = 2, first. At (0, 4) instead it falls 13,
  // t = sqrt(26) > 4, and the pair comes first (it stays 2 above the pair, never touching it).
  for (const double y : {-7.0, 4.0}) {
    Table t = make_table(10, 1, 3, 0, -1);
    t.c << -5, 2, 5, 2, 0, y;
    t.v << 1, 0, -1, 0, 0, 0;
    Collision got{};
    if (!checked_step(t, got, "a pair and a falling circle")) return;
    if (y < 0) {
      EXPECT_TRUE(is_wall(got, 2) && std::abs(got.time - 2) <= kTol)
          << explain("circle 2 (at rest at (0, -7)) to hit the wall at time 2, before the pair collides at time 4",
                     text("returned ", describe_collision(got)), kHintEarliest);
    } else {
      EXPECT_TRUE(is_pair(got, 0, 1) && std::abs(got.time - 4) <= kTol)
          << explain("circles 0 and 1 to collide at time 4, before circle 2 (at rest at (0, 4)) reaches the wall "
                     "at time sqrt(26)",
                     text("returned ", describe_collision(got)), kHintEarliest);
    }
  }
}

GRADED_TEST(Gravity, PairThatJustCollidedDoesNotCollideAgain, 2, after_due_date) {
  // Touching circles at (-1, 0) and (1, 0) flying apart with (-1, 0) and (1, 0) under
  // g = (0, -1): no collision; both reach the wall at the same time (either may be reported).
  Table t = make_table(10, 1, 2, 0, -1);
  t.c << -1, 0, 1, 0;
  t.v << -1, 0, 1, 0;
  const double expected = billiard::disc_in_circle_time(billiard::Vector(1, 0), billiard::Vector(1, 0),
                                                        billiard::Vector(0, -1), 9);
  Collision got{};
  if (!checked_step(t, got, "a touching pair flying apart")) return;
  EXPECT_TRUE(got.other == kWall && std::abs(got.time - expected) <= 1e-9)
      << explain(text("a wall hit after time ", expected, " (the touching pair flies apart and never collides)"),
                 text("returned ", describe_collision(got)), kHintRecollision);
}

GRADED_TEST(Gravity, WallTimesMatchTheQuarticOnRandomArcs, 3, after_due_date) {
  // 400 single circles: random places, velocities and gravity (strength 1e-2 to 1e2 of v^2 / R,
  // any direction, some at rest), against the library's quartic solver, which meets the wall
  // exactly at touching. The contact point and the reflected velocity follow from its time.
  std::mt19937_64 rng(0x9a17e5ULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int k = 0; k < 400; ++k) {
    const double R = k % 2 == 0 ? 10 : 2.5;
    const double a = R * (0.02 + 0.3 * unit(rng));
    const double L = R - a;
    const double radius = L * std::sqrt(unit(rng));
    const double phi = 2 * std::acos(-1.0) * unit(rng);
    Table t = make_table(R, a, 1, 0, 0);
    t.c << radius * std::cos(phi), radius * std::sin(phi);
    if (k % 7 != 0) t.v << normal(rng), normal(rng);
    const double strength = std::pow(10.0, 4 * unit(rng) - 2) / R;
    const double psi = 2 * std::acos(-1.0) * unit(rng);
    t.g << strength * std::cos(psi), strength * std::sin(psi);
    const Table before = t;
    const double expected =
        billiard::disc_in_circle_time(t.c.row(0), t.v.row(0), t.g, L);
    const std::string label = text("random arc ", k, ": R = ", R, ", a = ", a, ", start ", row(t.c, 0), ", velocity ",
                                   row(t.v, 0), ", g = ", vec(t.g));
    Collision got{};
    if (!checked_step(t, got, label)) return;
    const double scale = R / (before.v.row(0).norm() + std::sqrt(strength * R));
    if (!is_wall(got, 0) || !(std::abs(got.time - expected) <= 1e-9 * (expected + scale))) {
      ADD_FAILURE() << explain(text(label, ": the wall hit after time ", expected),
                               text("returned ", describe_collision(got)), kHintWallQuartic);
      return;
    }
    const Vector point = before.c.row(0) + expected * before.v.row(0) + (expected * expected / 2) * before.g;
    const Vector arriving = before.v.row(0) + expected * before.g;
    const Vector n = point.normalized();
    const Vector leaving = arriving - 2 * arriving.dot(n) * n;
    expect_row(t.c, 0, point, 1e-9 * R, text(label, ": the contact point"), kHintParabola);
    expect_row(t.v, 0, leaving, 1e-9 * (arriving.norm() + 1), text(label, ": the velocity after the bounce"),
               kHintContactVelocity);
    if (HasFailure()) return;
  }
}

// ---------------------------------------------------------------------------------------------
// 4. g = 0 is task 4.

GRADED_TEST(Gravity, ZeroGravityBehavesLikePropagate, 2, visible) {
  // Two cases of the propagate suite: from the centre with (1, 0) on R = 10, a = 1, the wall
  // at time 9, v' = (-1, 0); from (0, 3) with (1, 0) on R = 6, a = 1, the wall at (4, 3) at
  // time 4, v' = (-7/25, -24/25).
  Table t = make_table(10, 1, 1, 0, 0);
  t.v << 1, 0;
  Collision got{};
  if (!checked_step(t, got, "a circle from the centre with g = 0")) return;
  EXPECT_TRUE(is_wall(got, 0) && std::abs(got.time - 9) <= kTol)
      << explain("with g = 0, circle 0 to hit the wall at time 9, as propagate does",
                 text("returned ", describe_collision(got)), kHintZeroGravity);
  expect_row(t.v, 0, Vector(-1, 0), kTol, "the velocity after the head-on hit with g = 0", kHintZeroGravity);
  Table oblique = make_table(6, 1, 1, 0, 0);
  oblique.c << 0, 3;
  oblique.v << 1, 0;
  if (!checked_step(oblique, got, "an oblique wall hit with g = 0")) return;
  EXPECT_TRUE(is_wall(got, 0) && std::abs(got.time - 4) <= kTol)
      << explain("with g = 0, circle 0 from (0, 3) with (1, 0) on R = 6 to hit the wall at time 4",
                 text("returned ", describe_collision(got)), kHintZeroGravity);
  expect_row(oblique.c, 0, Vector(4, 3), kTol, "the contact point with g = 0", kHintZeroGravity);
  expect_row(oblique.v, 0, Vector(-7.0 / 25, -24.0 / 25), kTol, "the velocity after the oblique hit with g = 0",
             kHintZeroGravity);
}

GRADED_TEST(Gravity, ZeroGravityMatchesTheIndependentPropagateStep, 2, after_due_date) {
  // 20 random tables with g = 0, 50 steps each, every step from the oracle's shared state,
  // compared with the oracle (long double; events within 1e-9 of the earliest are ties).
  for (int k = 0; k < 20; ++k) {
    std::string label;
    Table t = billiard::testing::random_gravity_table(500 + static_cast<std::uint64_t>(k), k % 3 == 2, label);
    t.g.setZero();
    if (billiard::testing::max_speed(t.v) == 0) continue;
    for (int e = 0; e < 50; ++e) {
      const double scale = t.R / std::sqrt(t.v.squaredNorm());
      const auto expected = billiard::testing::oracle_step(t.R, t.a, t.c, t.v, 1e-9 * scale);
      Table mine = t;
      Collision got{};
      const std::string where = text(label, " with g = 0, step ", e);
      if (!checked_step(mine, got, where)) return;
      const billiard::testing::OracleEvent* match = nullptr;
      for (const auto& event : expected.events) {
        if (billiard::testing::same_event(event, got)) match = &event;
      }
      const auto& first = expected.events.front();
      if (match == nullptr || !(std::abs(got.time - match->time) <= 1e-9 * (match->time + scale))) {
        ADD_FAILURE() << explain(text("at ", where, ": ", billiard::testing::describe_event(first.circle, first.other),
                                      " after time ", first.time),
                                 text("returned ", describe_collision(got)), kHintZeroGravity);
        return;
      }
      const double position_error = (mine.c - match->coordinates).rowwise().norm().maxCoeff();
      const double velocity_error = (mine.v - match->velocities).rowwise().norm().maxCoeff();
      if (!(position_error <= 1e-9 * t.R) || !(velocity_error <= 1e-9 * std::sqrt(t.v.squaredNorm()))) {
        ADD_FAILURE() << explain(text("at ", where, ": the state after the step as propagate leaves it"),
                                 text("positions off by up to ", position_error, ", velocities by up to ",
                                      velocity_error),
                                 "with g = 0 every circle moves in a straight line and the collision rules are those "
                                 "of propagate; " + std::string(kHintZeroGravity));
        return;
      }
      billiard::testing::oracle_advance(expected, t.c, t.v);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 5. Long runs on the student's own trajectory: laws that every step must keep.

constexpr int kLongRunCircles = 20;
#ifdef NDEBUG
constexpr int kLongRunEvents = 2000;
#else
constexpr int kLongRunEvents = 300;  // Debug and sanitizer builds are ~100 times slower
#endif

Table long_run_table() {
  Table t;
  t.R = 10;
  t.a = 0.5;
  t.c = billiard::testing::scattered_circles(10, 0.5, kLongRunCircles, 7007);
  t.v = billiard::testing::gaussian_velocities(kLongRunCircles, 7007);
  t.g << 0.3, -1;
  return t;
}

GRADED_TEST(Gravity, TimesArePositiveFiniteAndIndicesValid, 2, after_due_date) {
  for (int k = 0; k < 12; ++k) {
    std::string label;
    Table t = billiard::testing::random_gravity_table(300 + static_cast<std::uint64_t>(k), k % 2 == 1, label);
    for (int e = 0; e < 150; ++e) {
      Collision got{};
      if (!checked_step(t, got, text(label, ", step ", e))) return;
      const bool circle_ok = got.circle >= 0 && got.circle < t.n();
      const bool other_ok = got.other == kWall || (got.other >= 0 && got.other < t.n() && got.other != got.circle);
      if (!(std::isfinite(got.time) && got.time >= 0) || !circle_ok || !other_ok) {
        ADD_FAILURE() << explain(text("at ", label, ", step ", e, ": a finite time >= 0, `circle` a row index 0..",
                                      t.n() - 1, " and `other` another row or kWall"),
                                 text("returned ", describe_collision(got)),
                                 "take only times t >= 0 (upward wall crossings, approaching pairs), skip events that "
                                 "never happen (infinite times), and return the indices of the colliding circles.");
        return;
      }
    }
  }
}

GRADED_TEST(Gravity, LongRunConservesMeanEnergy, 3, after_due_date) {
  // Free flight and elastic collisions conserve |v|^2 / 2 - g.r. Rounding makes it random-walk
  // by ~1e-16 per event and the roots are found to full precision: ~1e-14 after 2000 events;
  // 1e-9 of the size of its terms leaves a wide margin yet catches a wrong reflection at once.
  Table t = long_run_table();
  const long double start = billiard::testing::energy_per_circle(t);
  const double scale = billiard::testing::energy_scale(t);
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text("long run, event ", e))) return;
    const double drift = static_cast<double>(std::abs(billiard::testing::energy_per_circle(t) - start)) / scale;
    if (!(drift <= 1e-9)) {
      ADD_FAILURE() << explain(
          text("the energy per circle, (1/n) sum (|v|^2 / 2 - g.r), to stay constant (change below 1e-9 of ",
               "(1/n) sum (|v|^2 / 2 + |g||r|) = ", scale, ") over ", kLongRunEvents, " events of ", kLongRunCircles,
               " circles under g = ", vec(t.g)),
          text("after event ", e, " (", describe_collision(got), ") it changed by ", drift, " of that"),
          "energy is lost or gained when a circle is moved or reflected wrongly: move on the parabola "
          "r + v t + g t^2/2 with v += g t, reflect the velocity at contact at the wall (v' = v - 2 (v.n) n, "
          "n = r / |r|), exchange only normal components between circles, and find the wall time to full "
          "precision.");
      return;
    }
  }
}

GRADED_TEST(Gravity, LongRunKeepsCirclesApartAndOnTheTable, 3, after_due_date) {
  Table t = long_run_table();
  for (int e = 1; e <= kLongRunEvents; ++e) {
    Collision got{};
    if (!checked_step(t, got, text("long run, event ", e))) return;
    int i = -1, j = -1, w = -1;
    const double overlap = billiard::testing::worst_overlap(t.c, t.a, &i, &j);
    const double protrusion = billiard::testing::worst_protrusion(t.c, t.R, t.a, &w);
    // Positions at an event are exact up to rounding (~1e-15 of R = 10).
    if (!(overlap <= 1e-9)) {
      ADD_FAILURE() << explain("no two circles to overlap (by more than 1e-9) at any event",
                               text("after event ", e, " (", describe_collision(got), ") circles ", i, " and ", j,
                                    " overlap by ", overlap),
                               "a missed or late pair event lets circles pass into each other: " +
                                   std::string(kHintPairTime));
      return;
    }
    if (!(protrusion <= 1e-9)) {
      ADD_FAILURE() << explain("every circle to stay on the table (|r| <= R - a + 1e-9) at every event",
                               text("after event ", e, " (", describe_collision(got), ") circle ", w,
                                    " sticks out by ", protrusion),
                               "a circle escapes when a wall hit is missed: take the FIRST upward crossing of the "
                               "quartic (check every monotone piece), and bounce a circle on the wall that moves "
                               "outward at once.");
      return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 6. Step by step against the finished library, from shared random states.

// Steps `steps` times from each table: the student's step and the library's from the same
// state, compared; then both go on from the library's state (tidied, see gravity_support.hpp),
// so that one mistake never spoils the following steps.
void run_against_library(std::uint64_t first_seed, int tables, bool crowded, int steps) {
  for (int k = 0; k < tables; ++k) {
    std::string label;
    Table t = billiard::testing::random_gravity_table(first_seed + static_cast<std::uint64_t>(k), crowded, label);
    for (int e = 0; e < steps; ++e) {
      billiard::testing::tidy_for_library(t);
      const auto lib = billiard::testing::library_step(t);
      ASSERT_TRUE(lib.ok) << "test error at " << label << ", step " << e << ": " << lib.problem;
      Table mine = t;
      Collision got{};
      const std::string where = text(label, ", step ", e);
      if (!checked_step(mine, got, where)) return;
      const std::string problem = billiard::testing::compare_with_library(
          t, got, mine, lib, where, kHintEarliest, kHintParabola, kHintContactVelocity, kHintPairVelocity);
      if (!problem.empty()) {
        ADD_FAILURE() << problem;
        return;
      }
      t.c = lib.c;
      t.v = lib.v;
    }
  }
}

GRADED_TEST(Gravity, MatchesTheLibraryStepByStepOnRandomTables, 3, after_due_date) {
  // 30 tables: 1 to 12 circles, R from 1 to 100, speeds 0.01 to 30, g from weak to strong in
  // every direction, some circles at rest; 40 steps each.
  run_against_library(1000, 30, false, 40);
}

GRADED_TEST(Gravity, MatchesTheLibraryStepByStepOnCrowdedTables, 3, after_due_date) {
  // 12 tables with 15 to 30 circles filling 20% to 30% of the table: mostly pair events,
  // many of them between circles falling onto each other; 40 steps each.
  run_against_library(2000, 12, true, 40);
}

// ---------------------------------------------------------------------------------------------
// 7. mean_energy, more cases.

GRADED_TEST(Gravity, MeanEnergyOfNoCirclesIsZero, 1, after_due_date) {
  const Coordinates c(0, 2);
  const Velocities v(0, 2);
  const double got = billiard::mean_energy(0, c, v, Vector(0, -1));
  EXPECT_EQ(got, 0.0) << explain("mean_energy = 0 for n = 0", text("returned ", got),
                                 "with no circles return 0 instead of dividing 0 by n = 0 (NaN).");
}

GRADED_TEST(Gravity, MeanEnergyMatchesItsDefinitionForAnyGravity, 1, after_due_date) {
  for (int k = 0; k < 20; ++k) {
    std::string label;
    const Table t = billiard::testing::random_gravity_table(700 + static_cast<std::uint64_t>(k), k % 2 == 1, label);
    const double expected = static_cast<double>(billiard::testing::energy_per_circle(t));
    draw_if_failing(t.c, t.v, t.g);
    const double got = billiard::mean_energy(t.n(), t.c, t.v, t.g);
    if (!(std::abs(got - expected) <= 1e-12 * billiard::testing::energy_scale(t))) {
      ADD_FAILURE() << explain(text("mean_energy = ", expected, " for ", label), text("returned ", got),
                               "mean_energy = (1/n) sum_i (|v_i|^2 / 2 - g.r_i), with both components of g and r.");
      return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 8. Argument checks: std::invalid_argument naming the argument, and the state left unchanged.

Table two_circles() {
  Table t = make_table(10, 1, 2, 0, -1);
  t.c << -5, 0, 5, 0;
  t.v << 1, 0, -1, 0;
  return t;
}

// Calls propagate_gravity with the given arguments, expects std::invalid_argument naming
// `argument`, and checks that coordinates and velocities were left as they were.
void expect_refused(double R, double a, int n, Coordinates c, Velocities v, const Vector& g,
                    const std::string& situation, const std::string& argument, const std::string& hint) {
  const Coordinates c0 = c;
  const Velocities v0 = v;
  billiard::testing::expect_invalid_argument([&] { billiard::propagate_gravity(R, a, n, c, v, g); }, situation,
                                             argument, hint);
  EXPECT_TRUE(c.rows() == c0.rows() && c == c0 && v.rows() == v0.rows() && v == v0)
      << explain(text("coordinates and velocities unchanged after refusing ", situation),
                 "they were changed before the error was thrown",
                 "check every argument first, before moving anything.");
}

GRADED_TEST(Gravity, RejectsGravityThatIsNotFinite, 1, after_due_date) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vector& g : {Vector(nan, -1), Vector(0, inf), Vector(-inf, 0), Vector(1e51, 0)}) {
    const Table t = two_circles();
    expect_refused(t.R, t.a, 2, t.c, t.v, g, text("g = ", vec(g)), "g",
                   "check g with checks::vector(g, \"g\"): both components finite and at most 1e50.");
  }
}

GRADED_TEST(Gravity, RejectsBadRadii, 1, after_due_date) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Table t = two_circles();
  for (const double R : {0.0, -10.0, nan}) {
    expect_refused(R, 1, 2, t.c, t.v, t.g, text("table_radius = ", R), "table_radius",
                   "check the radii with checks::table(table_radius, circle_radius, n).");
  }
  for (const double a : {0.0, -1.0, nan, 10.0}) {
    expect_refused(10, a, 2, t.c, t.v, t.g, text("circle_radius = ", a, " on a table of radius 10"), "circle_radius",
                   "check the radii with checks::table(table_radius, circle_radius, n).");
  }
}

GRADED_TEST(Gravity, RejectsRowCountsThatDoNotMatchN, 1, after_due_date) {
  const Table t = two_circles();
  Coordinates three(3, 2);
  three << -5, 0, 5, 0, 0, 5;
  expect_refused(10, 1, 2, three, t.v, t.g, "coordinates with 3 rows for n = 2", "coordinates",
                 "check both matrices with checks::rows(coordinates, n, \"coordinates\") and the same for velocities.");
  Velocities one(1, 2);
  one << 1, 0;
  expect_refused(10, 1, 2, t.c, one, t.g, "velocities with 1 row for n = 2", "velocities",
                 "check both matrices with checks::rows(coordinates, n, \"coordinates\") and the same for velocities.");
}

GRADED_TEST(Gravity, RejectsStatesWithNoEventOrBadPlacement, 1, after_due_date) {
  // No circles: nothing can collide. All at rest with g = 0: nothing ever moves. (All at rest
  // with g != 0 is valid: they fall; see CircleDroppedFromRestFallsToTheWall.)
  expect_refused(10, 1, 0, Coordinates(0, 2), Velocities(0, 2), Vector(0, -1), "n = 0 (no circles)", "",
                 "with no circles there is no next event: throw std::invalid_argument.");
  Table rest = two_circles();
  rest.v.setZero();
  expect_refused(10, 1, 2, rest.c, rest.v, Vector(0, 0), "all circles at rest and g = 0", "",
                 "with g = 0 and every circle at rest no event ever happens: throw std::invalid_argument instead of "
                 "returning an infinite time.");
  Table overlapping = two_circles();
  overlapping.c << -0.5, 0, 0.5, 0;
  expect_refused(10, 1, 2, overlapping.c, overlapping.v, overlapping.g, "two overlapping circles", "coordinates",
                 "check the placement as propagate does: checks::placement(table_radius, circle_radius, coordinates).");
  Table outside = two_circles();
  outside.c << -9.5, 0, 5, 0;
  expect_refused(10, 1, 2, outside.c, outside.v, outside.g, "a circle sticking out of the table", "coordinates",
                 "check the placement as propagate does: checks::placement(table_radius, circle_radius, coordinates).");
}

GRADED_TEST(Gravity, MeanEnergyRejectsBadArguments, 1, after_due_date) {
  const Table t = two_circles();
  billiard::testing::expect_invalid_argument(
      [&] { billiard::mean_energy(2, t.c, t.v, Vector(std::numeric_limits<double>::quiet_NaN(), 0)); }, "g = (nan, 0)",
      "g", "check g with checks::vector(g, \"g\").");
  Coordinates three(3, 2);
  three << -5, 0, 5, 0, 0, 5;
  billiard::testing::expect_invalid_argument([&] { billiard::mean_energy(2, three, t.v, t.g); },
                                             "coordinates with 3 rows for n = 2", "coordinates",
                                             "check both matrices with checks::rows(...).");
  Velocities one(1, 2);
  one << 1, 0;
  billiard::testing::expect_invalid_argument([&] { billiard::mean_energy(2, t.c, one, t.g); },
                                             "velocities with 1 row for n = 2", "velocities",
                                             "check both matrices with checks::rows(...).");
  billiard::testing::expect_invalid_argument([&] { billiard::mean_energy(-1, t.c, t.v, t.g); }, "n = -1", "n",
                                             "check n with checks::rows(...), which refuses n < 0.");
}

}  // namespace
