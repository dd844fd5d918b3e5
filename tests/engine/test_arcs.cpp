// Curved walls (circular arcs): times of impact a person can check by hand, gravity cases against
// a direct numeric search, the arc as a wall of the engine, curved containers (stadium, Sinai
// billiard, mushroom, union of circles) over many collisions, and the argument checks.
#include "billiard/engine/simulation.hpp"
#include "time_of_impact.hpp"
#include "wall_geometry.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

using billiard::kNever;
using billiard::Vector;

namespace {

const Vector kNoGravity = Vector::Zero();
constexpr double kPi = 3.14159265358979323846;

// Is direction d on the arc from `start` counter-clockwise through `sweep`? Written with cross
// products, independently of the engine's angle arithmetic.
bool on_arc_by_cross_products(double start, double sweep, const Vector& d) {
  if (sweep >= 2 * kPi) return true;
  const Vector s(std::cos(start), std::sin(start));
  const Vector e(std::cos(start + sweep), std::sin(start + sweep));
  const bool after_start = billiard::cross(s, d) >= 0;
  const bool before_end = billiard::cross(d, e) >= 0;
  return sweep <= kPi ? (after_start && before_end) : (after_start || before_end);
}

// Direct numeric search for the first contact of a disc with an arc: |r(t)| - reach sampled on
// a fine grid up to t_end, each sign change in the contact direction refined by bisection, the
// first one whose direction lies on the arc.
double numeric_arc_time(const Vector& r, const Vector& v, const Vector& g, double rho, double start, double sweep,
                        double radius, double t_end) {
  auto at = [&](double t) -> Vector { return r + v * t + 0.5 * t * t * g; };
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
  for (const Vector& v : {Vector(2, 0), Vector(1.2, 1.6), Vector(0, -2)}) {
    EXPECT_DOUBLE_EQ(billiard::disc_arc_time(Vector::Zero(), v, kNoGravity, 5, 0, 2 * kPi, 1), 2.0);
  }
}

TEST(ArcTime, DiscInsideHitsTheConcaveArcOnlyWhereTheArcIs) {
  // The right quarter of the circle rho = 5 (angles -45 to +45 degrees), a disc of radius 1 at
  // the centre: moving right it meets the arc at t = 4 / 2; moving left it leaves through the gap.
  EXPECT_DOUBLE_EQ(billiard::disc_arc_time(Vector::Zero(), Vector(2, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), 2.0);
  EXPECT_EQ(billiard::disc_arc_time(Vector::Zero(), Vector(-2, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), kNever);
  // From (0, 3) moving right: |r(t)|^2 = t^2 + 9 = 16 at t = sqrt(7), direction (sqrt 7, 3) at
  // 48.6 degrees: past the end of the arc, so no contact.
  EXPECT_EQ(billiard::disc_arc_time(Vector(0, 3), Vector(1, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), kNever);
  // From (0, 2): t = sqrt(12), direction at 30 degrees: on the arc.
  EXPECT_NEAR(billiard::disc_arc_time(Vector(0, 2), Vector(1, 0), kNoGravity, 5, -kPi / 4, kPi / 2, 1), std::sqrt(12.0),
              1e-15);
}

TEST(ArcTime, ConvexObstacleAtGrazingDistanceAndJustInsideAndOutsideIt) {
  // Obstacle rho = 2, disc radius 1 moving right along y = b from x = -10: contact distance 3.
  const double rho = 2, a = 1;
  auto time_at = [&](double b) { return billiard::disc_arc_time(Vector(-10, b), Vector(1, 0), kNoGravity, rho, 0, 2 * kPi, a); };
  // Exactly grazing: touches at x = 0, t = 10 (no effect on the velocity, see the engine test).
  EXPECT_DOUBLE_EQ(time_at(3.0), 10.0);
  // Just inside: contact at x = -sqrt(9 - b^2).
  const double b = 3 - 1e-3;
  EXPECT_NEAR(time_at(b), 10 - std::sqrt(9 - b * b), 1e-12);
  // Just outside: never.
  EXPECT_EQ(time_at(3 + 1e-3), kNever);
  // Moving away: never; a hair inside the contact distance and approaching: now.
  EXPECT_EQ(billiard::disc_arc_time(Vector(-4, 0), Vector(-1, 0), kNoGravity, rho, 0, 2 * kPi, a), kNever);
  EXPECT_EQ(billiard::disc_arc_time(Vector(-3 + 1e-15, 0), Vector(1, 0), kNoGravity, rho, 0, 2 * kPi, a), 0.0);
}

TEST(ArcTime, GapsAndEndPoints) {
  // The upper half of the circle rho = 5 (angles 0 to 180 degrees), disc radius 0.5.
  const double rho = 5, a = 0.5, start = 0, sweep = kPi;
  auto time = [&](const Vector& r, const Vector& v) { return billiard::disc_arc_time(r, v, kNoGravity, rho, start, sweep, a); };
  // Moving right below the arc (y = -2): crosses the missing half twice, no contact.
  EXPECT_EQ(time(Vector(-8, -2), Vector(1, 0)), kNever);
  // From the centre straight down: out through the gap.
  EXPECT_EQ(time(Vector::Zero(), Vector(0, -1)), kNever);
  // From (0, -8) straight up: in through the gap, meets the inside of the arc at y = 4.5, t = 12.5.
  EXPECT_DOUBLE_EQ(time(Vector(0, -8), Vector(0, 1)), 12.5);
  // From (0, 8) straight down: the outside of the arc at y = 5.5, t = 2.5.
  EXPECT_DOUBLE_EQ(time(Vector(0, 8), Vector(0, -1)), 2.5);
  // Aimed at the end point (5, 0) from below: the arc itself is never touched (the end point is a
  // separate wall, met at t = 3 - 0.5 = 2.5).
  EXPECT_EQ(time(Vector(5, -3), Vector(0, 1)), kNever);
  EXPECT_DOUBLE_EQ(billiard::disc_point_time(Vector(5, -3), Vector(0, 1), kNoGravity, Vector(5, 0), a), 2.5);
}

TEST(ArcTime, RoundingConventionOnBothFaces) {
  // A hair beyond the concave contact (|r| = 4.5 + 1e-15) moving out: now; moving in: later.
  const Vector r(4.5 + 1e-15, 0);
  EXPECT_EQ(billiard::disc_arc_time(r, Vector(1, 0), kNoGravity, 5, -1, 2, 0.5), 0.0);
  EXPECT_GT(billiard::disc_arc_time(r, Vector(-1, 0), kNoGravity, 5, -1, 2, 0.5), 8.9);
  // Just bounced off the convex face (|r| = 5.5 exactly, moving out): never.
  EXPECT_EQ(billiard::disc_arc_time(Vector(5.5, 0), Vector(1, 0.3), kNoGravity, 5, -1, 2, 0.5), kNever);
}

TEST(ArcTime, UnderGravityADiscDroppedIntoACupFallsThroughTheOpenTop) {
  // The lower half of rho = 5 (angles 180 to 360 degrees) as a cup; a disc of radius 0.5 at rest
  // at (1, 8), g = (0, -1): it falls through the open top and meets the inside of the cup at
  // y = -sqrt(4.5^2 - 1), after falling 8 + sqrt(19.25): t = sqrt(2 (8 + sqrt(19.25))).
  const double t = billiard::disc_arc_time(Vector(1, 8), Vector::Zero(), Vector(0, -1), 5, kPi, kPi, 0.5);
  EXPECT_NEAR(t, std::sqrt(2 * (8 + std::sqrt(19.25))), 1e-12);
}

TEST(ArcTime, UnderGravityThrownUpThroughTheGapIntoADome) {
  // The upper half of rho = 5 as a dome, disc radius 0.5 thrown up from (0, -8) at speed 6, g = 1:
  // y(t) = -8 + 6 t - t^2 / 2 reaches 4.5 (inside the dome) at t = 6 - sqrt(11).
  const double t = billiard::disc_arc_time(Vector(0, -8), Vector(0, 6), Vector(0, -1), 5, 0, kPi, 0.5);
  EXPECT_NEAR(t, 6 - std::sqrt(11.0), 1e-12);
}

TEST(ArcTime, UnderGravityAgreesWithADirectNumericSearch) {
  // Throws past arcs of several shapes: some pass the gap and come back onto the other face.
  struct Case {
    Vector r, v, g;
    double rho, start, sweep, radius;
  };
  const Case cases[] = {
      {Vector(7, -1), Vector(-0.8, 6), Vector(0, -1), 5, 0, kPi, 0.5},        // over the end, onto the dome
      {Vector(0, -8), Vector(0.7, 6.5), Vector(0, -1), 5, 0, kPi, 0.5},       // up into the dome, off centre
      {Vector(-9, 2), Vector(3, 1), Vector(0.2, -1), 4, kPi / 3, kPi, 0.3},   // tilted gravity, left arc
      {Vector(1, 1), Vector(2, 0.5), Vector(0, -2), 3, -kPi / 2, 1.5 * kPi, 0.25},  // inside a 3/4 circle
      {Vector(0, 6), Vector(-0.5, 0), Vector(0, -1), 3, 0, 2 * kPi, 1},       // onto a full circle obstacle
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

// ---- The arc as a wall of the engine ----

namespace {

using engine_test::make_disc;
using engine_test::physics;

// The first event of a one-disc simulation.
billiard::EventRecord first_event(billiard::Simulation& sim) {
  sim.set_log_events(true);
  const billiard::AdvanceResult result = sim.advance(1);
  EXPECT_EQ(result.collisions, 1);
  EXPECT_EQ(sim.validate(), std::nullopt);
  return sim.event_log().empty() ? billiard::EventRecord{} : sim.event_log().back();
}

}  // namespace

TEST(ArcWall, DiscThroughTheGapMeetsTheInsideOfAFreeArc) {
  // The upper half of rho = 5 in the box [-10, 10]^2; a disc of radius 0.5 from (0, -8) moving
  // up passes the open lower half and meets the inside of the arc at y = 4.5, t = 12.5, and
  // bounces straight back.
  billiard::Container container = billiard::box(Vector(-10, -10), Vector(10, 10));
  const int arc = container.add_arc(Vector(0, 0), 5, 0, kPi);
  billiard::Simulation sim(container);
  sim.add_disc(make_disc(Vector(0, -8), Vector(0, 1), 0.5));
  const billiard::EventRecord e = first_event(sim);
  EXPECT_EQ(e.wall, arc);
  EXPECT_DOUBLE_EQ(e.time, 12.5);
  EXPECT_NEAR(e.velocity.x(), 0, 1e-15);
  EXPECT_DOUBLE_EQ(e.velocity.y(), -1);
  // The arc's end points are point walls.
  int points = 0;
  for (const billiard::WallShape& w : sim.container().walls()) {
    if (w.kind == billiard::WallKind::Point && ((w.a - Vector(5, 0)).norm() < 1e-14 || (w.a - Vector(-5, 0)).norm() < 1e-14)) ++points;
  }
  EXPECT_EQ(points, 2);
}

TEST(ArcWall, DiscAimedAtAnEndPointHitsThePoint) {
  // From (5, -3) straight up at the end point (5, 0): contact at t = 3 - 0.5 = 2.5, head on.
  billiard::Container container = billiard::box(Vector(-10, -10), Vector(10, 10));
  container.add_arc(Vector(0, 0), 5, 0, kPi);
  billiard::Simulation sim(container);
  sim.add_disc(make_disc(Vector(5, -3), Vector(0, 1), 0.5));
  const billiard::EventRecord e = first_event(sim);
  ASSERT_GE(e.wall, 0);
  EXPECT_EQ(sim.container().walls()[static_cast<std::size_t>(e.wall)].kind, billiard::WallKind::Point);
  EXPECT_DOUBLE_EQ(e.time, 2.5);
  EXPECT_NEAR(e.velocity.y(), -1, 1e-15);
}

TEST(ArcWall, DiscAimedAtTheGapReachesTheBoxWall) {
  // Moving right along y = -2 under the upper-half arc: nothing until the box wall x = 10 at
  // t = (9.5 - (-8)) = 17.5.
  billiard::Container container = billiard::box(Vector(-10, -10), Vector(10, 10));
  container.add_arc(Vector(0, 0), 5, 0, kPi);
  billiard::Simulation sim(container);
  sim.add_disc(make_disc(Vector(-8, -2), Vector(1, 0), 0.5));
  const billiard::EventRecord e = first_event(sim);
  EXPECT_EQ(sim.container().walls()[static_cast<std::size_t>(e.wall)].kind, billiard::WallKind::Segment);
  EXPECT_DOUBLE_EQ(e.time, 17.5);
}

TEST(ArcWall, DiscObstacleGrazedAndHit) {
  // Obstacle rho = 2 at the origin, disc radius 1 along y = b from x = -10 at speed 1.
  auto run = [](double b) {
    billiard::Container container = billiard::box(Vector(-20, -20), Vector(20, 20));
    container.add_obstacle(Vector(0, 0), 2);
    billiard::Simulation sim(container);
    sim.add_disc(make_disc(Vector(-10, b), Vector(1, 0), 1));
    return first_event(sim);
  };
  // Grazing at distance 3: touches at t = 10, velocity unchanged (v.n = 0).
  const billiard::EventRecord graze = run(3);
  EXPECT_DOUBLE_EQ(graze.time, 10);
  EXPECT_NEAR(graze.velocity.x(), 1, 1e-15);
  EXPECT_NEAR(graze.velocity.y(), 0, 1e-15);
  // Just inside: contact at x = -sqrt(9 - b^2), mirror reflection about n = (x, b) / 3.
  const double b = 2.5;
  const billiard::EventRecord hit = run(b);
  const double x = -std::sqrt(9 - b * b);
  EXPECT_NEAR(hit.time, 10 + x, 1e-12);
  const Vector n = Vector(x, b) / 3, v(1, 0);
  const Vector expected = v - 2 * v.dot(n) * n;
  EXPECT_NEAR(hit.velocity.x(), expected.x(), 1e-12);
  EXPECT_NEAR(hit.velocity.y(), expected.y(), 1e-12);
  // Just outside: it reaches the box wall x = 20 at t = 29.
  EXPECT_DOUBLE_EQ(run(3.001).time, 29);
}

TEST(ArcWall, DiscsInsideAFreeRingStayInsideItUnderGravity) {
  // A whole free circle of radius 5 at (3, 2) inside a box: discs placed inside it stay there.
  billiard::Container container = billiard::box(Vector(-10, -10), Vector(20, 20));
  container.add_arc(Vector(3, 2), 5, 1, 1 + 2 * kPi);
  billiard::Simulation sim(container, physics(Vector(0.1, -1)));
  for (int k = 0; k < 6; ++k) sim.add_disc(make_disc(Vector(3 + 1.2 * (k - 2.5), 2 + 0.3 * k), Vector(std::cos(k), std::sin(k)), 0.4));
  const double energy = sim.kinetic_energy() + sim.potential_energy();
  sim.advance(20000);
  EXPECT_EQ(sim.validate(), std::nullopt);
  const billiard::State s = sim.current_state();
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    EXPECT_LE((Vector(s.positions.row(i)) - Vector(3, 2)).norm(), 5 - 0.4 + 1e-9);
  }
  EXPECT_NEAR(sim.kinetic_energy() + sim.potential_energy(), energy, 1e-9 * energy);
}

// ---- Curved containers over many collisions ----

namespace {

// Runs `events` collisions in blocks, checking every event's discs (set_check_event_discs) and
// the whole system (validate) after each block; returns the relative change of kinetic plus
// potential energy.
double long_run(billiard::Simulation& sim, std::int64_t events, std::int64_t block) {
  const double e0 = sim.kinetic_energy() + sim.potential_energy();
  sim.set_check_event_discs(true);
  for (std::int64_t done = 0; done < events;) {
    const billiard::AdvanceResult result = sim.advance(std::min(block, events - done));
    EXPECT_FALSE(result.stuck) << result.stuck_reason;
    EXPECT_EQ(sim.last_problem(), std::nullopt) << "after " << done << " collisions";
    EXPECT_EQ(sim.validate(), std::nullopt) << "after " << done << " collisions";
    if (result.collisions == 0 || sim.last_problem().has_value()) return kNever;
    done += result.collisions;
  }
  const double error = std::abs(sim.kinetic_energy() + sim.potential_energy() - e0) / std::abs(e0);
  std::printf("relative energy error %.3g after %lld collisions\n", error, static_cast<long long>(events));
  return error;
}

}  // namespace

TEST(CurvedContainer, StressStadiumUnderGravityKeepsEnergyOverAMillionCollisions) {
  // 100 discs of radius 0.4 in a stadium of radius 10 and length 10 under g = (0.2, -1). Energy
  // (kinetic plus potential) changes only by rounding: about 1e-16 relative per collision as a
  // random walk, larger under gravity because positions enter the potential energy (the gravity
  // tests allow 1e-10 over 2e4 collisions); over 1e6 collisions we allow 1e-9.
  billiard::Simulation sim(billiard::stadium(Vector(0, 0), 10, 10), physics(Vector(0.2, -1)));
  sim.add_random_discs(100, 0.4, 1.0, 5.0, 31);
  EXPECT_LT(long_run(sim, 1000000, 5000), 1e-9);
}

TEST(CurvedContainer, StadiumUnderGravityKeepsEnergy) {
  // The stress test above, shorter (1e5 collisions, a second): the same bound.
  billiard::Simulation sim(billiard::stadium(Vector(0, 0), 10, 10), physics(Vector(0.2, -1)));
  sim.add_random_discs(100, 0.4, 1.0, 5.0, 35);
  EXPECT_LT(long_run(sim, 100000, 5000), 1e-9);
}

TEST(CurvedContainer, SinaiBilliardKeepsEnergy) {
  billiard::Simulation sim(billiard::sinai_billiard(Vector(0, 0), Vector(20, 20), 5));
  sim.add_random_discs(100, 0.4, 1.0, 1.0, 32);
  EXPECT_LT(long_run(sim, 200000, 5000), 1e-11);
  // No disc inside the obstacle.
  const billiard::State s = sim.current_state();
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    EXPECT_GE((Vector(s.positions.row(i)) - Vector(10, 10)).norm(), 5 + 0.4 - 1e-9);
  }
}

TEST(CurvedContainer, MushroomKeepsEnergy) {
  billiard::Simulation sim(billiard::mushroom(Vector(0, 0), 10, 6, 8));
  sim.add_random_discs(100, 0.4, 1.0, 1.0, 33);
  EXPECT_LT(long_run(sim, 200000, 5000), 1e-11);
}

TEST(CurvedContainer, UnionOfCirclesKeepsEnergy) {
  // Three overlapping circles with a concave corner wherever two boundaries meet, and a fourth
  // circle inside the first (no boundary of its own).
  billiard::Coordinates centres(4, 2);
  centres << 0, 0, 12, 0, 6, 9, 1, 1;
  billiard::Simulation sim(billiard::union_of_circles(centres, {8, 6, 5, 2}));
  int arcs = 0, points = 0;
  for (const billiard::WallShape& w : sim.container().walls()) {
    arcs += w.kind == billiard::WallKind::Arc ? 1 : 0;
    points += w.kind == billiard::WallKind::Point ? 1 : 0;
  }
  // The boundary is one closed curve (the middle is covered): one corner where each two arcs
  // meet, so as many point walls as arcs, and at least one arc per outer circle.
  EXPECT_EQ(arcs, points);
  EXPECT_GE(arcs, 3);
  sim.add_random_discs(100, 0.3, 1.0, 1.0, 34);
  EXPECT_LT(long_run(sim, 200000, 5000), 1e-11);
}

// ---- Inside tests and bad arguments ----

TEST(CurvedContainer, InsideTestsOfTheCurvedOutlines) {
  // A disc is accepted only inside the container and clear of its walls.
  auto accepts = [](const billiard::Container& container, const Vector& p, double a) {
    billiard::Simulation sim(container);
    try {
      sim.add_disc(make_disc(p, Vector(1, 0), a));
      return true;
    } catch (const std::invalid_argument&) {
      return false;
    }
  };
  const billiard::Container stadium = billiard::stadium(Vector(1, 2), 3, 4);
  EXPECT_TRUE(accepts(stadium, Vector(1, 2), 0.5));
  EXPECT_TRUE(accepts(stadium, Vector(1 + 2 + 2.4, 2), 0.5));   // in the right half circle
  EXPECT_FALSE(accepts(stadium, Vector(1 + 2 + 2.6, 2), 0.5));  // overlaps it
  EXPECT_FALSE(accepts(stadium, Vector(1 + 2 + 3.5, 2), 0.5));  // outside
  EXPECT_FALSE(accepts(stadium, Vector(1, 2 + 3.5), 0.5));      // above the top side
  EXPECT_FALSE(accepts(stadium, Vector(1 + 2 + 2.5, 2 + 2.5), 0.1));  // beyond the corner of the box of the arcs
  const billiard::Container sinai = billiard::sinai_billiard(Vector(0, 0), Vector(10, 10), 2);
  EXPECT_TRUE(accepts(sinai, Vector(1, 1), 0.5));
  EXPECT_FALSE(accepts(sinai, Vector(5, 5), 0.5));  // inside the obstacle
  EXPECT_TRUE(accepts(sinai, Vector(5, 7.6), 0.5));
  EXPECT_FALSE(accepts(sinai, Vector(5, 7.4), 0.5));  // overlaps the obstacle
  const billiard::Container mushroom = billiard::mushroom(Vector(0, 0), 5, 2, 4);
  EXPECT_TRUE(accepts(mushroom, Vector(0, -3), 0.5));   // in the stem
  EXPECT_TRUE(accepts(mushroom, Vector(3, 0.6), 0.5));  // in the cap, above the ledge
  EXPECT_FALSE(accepts(mushroom, Vector(3, -1), 0.5));  // beside the stem, under the cap
  EXPECT_TRUE(accepts(mushroom, Vector(0, 0), 0.5));    // where the stem meets the cap
  billiard::Container table_with_obstacle = billiard::circular_table(10);
  table_with_obstacle.add_obstacle(Vector(3, 0), 2);
  EXPECT_TRUE(accepts(table_with_obstacle, Vector(0, 0), 0.5));
  EXPECT_TRUE(accepts(table_with_obstacle, Vector(-8, 0), 0.5));
  EXPECT_FALSE(accepts(table_with_obstacle, Vector(3, 0.5), 0.5));  // inside the obstacle
  EXPECT_FALSE(accepts(table_with_obstacle, Vector(9.8, 0), 0.5));  // outside the table
  billiard::Coordinates centres(2, 2);
  centres << 0, 0, 3, 0;
  const billiard::Container pair = billiard::union_of_circles(centres, {2, 2});
  EXPECT_TRUE(accepts(pair, Vector(1.5, 0), 0.5));
  EXPECT_TRUE(accepts(pair, Vector(4, 0), 0.5));
  EXPECT_FALSE(accepts(pair, Vector(1.5, 1.5), 0.5));  // at the upper corner where the circles meet
  EXPECT_FALSE(accepts(pair, Vector(1.5, 3), 0.5));    // outside both
}

namespace {
// The message of the std::invalid_argument that `call` throws ("no exception" if it returns).
template <class Call>
std::string refusal(Call call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no exception";
}

using engine_test::same_walls;

// Runs `call` (a shape function), expects std::invalid_argument whose message contains `piece`.
template <class Call>
void expect_refused(Call call, const std::string& piece) {
  const std::string message = refusal(call);
  EXPECT_NE(message.find(piece), std::string::npos) << message << " lacks " << piece;
}

// Runs `call` (an add_ call on `container`), expects std::invalid_argument whose message contains
// `piece`, and the container unchanged.
template <class Call>
void expect_refused(const billiard::Container& container, Call call, const std::string& piece) {
  const std::vector<billiard::WallShape> walls = container.walls();
  const std::size_t outlines = container.outlines().size();
  expect_refused(call, piece);
  EXPECT_TRUE(same_walls(container.walls(), walls)) << piece;
  EXPECT_EQ(container.outlines().size(), outlines) << piece;
}

// A wall may not cross a disc: with the container fixed before the discs, add_disc refuses a disc
// that the container's walls would cross (or leave outside), naming `piece`, and adds nothing.
void expect_disc_refused(const billiard::Container& container, const billiard::Disc& disc, const std::string& piece) {
  billiard::Simulation sim(container);
  const std::string message = refusal([&] { sim.add_disc(disc); });
  EXPECT_NE(message.find(piece), std::string::npos) << message << " lacks " << piece;
  EXPECT_EQ(sim.size(), 0) << piece;
}
}  // namespace

TEST(CurvedContainer, BadArgumentsAreRefusedNamingTheArgumentAndLeaveTheStateUnchanged) {
  billiard::Container container = billiard::box(Vector(-50, -50), Vector(50, 50));
  const billiard::Disc disc = make_disc(Vector(0, 0), Vector(1, 0), 1);
  const double nan = std::nan("");
  expect_refused(container, [&] { container.add_arc(Vector(nan, 0), 1, 0, 1); }, "add_arc: centre");
  expect_refused(container, [&] { container.add_arc(Vector(5, 5), -1, 0, 1); }, "add_arc: radius");
  expect_refused(container, [&] { container.add_arc(Vector(5, 5), 1, kNever, 1); }, "add_arc: start_angle");
  expect_refused(container, [&] { container.add_arc(Vector(5, 5), 1, 0, nan); }, "add_arc: end_angle");
  expect_refused(container, [&] { container.add_arc(Vector(5, 5), 1, 1, 1); }, "end_angle - start_angle");
  expect_refused(container, [&] { container.add_arc(Vector(5, 5), 1, 0, 7); }, "end_angle - start_angle");
  {
    billiard::Container with_arc = container;
    const int arc = with_arc.add_arc(Vector(0, 1.5), 1, kPi, 2 * kPi);
    expect_disc_refused(with_arc, disc, "disc 0 at (0, 0) overlaps wall " + std::to_string(arc));
  }
  {
    billiard::Container with_obstacle = container;
    with_obstacle.add_obstacle(Vector(0, 0), 3);
    expect_disc_refused(with_obstacle, disc, "disc 0 at (0, 0) is outside the walls");
  }
  expect_refused(container, [&] { container.add_obstacle(Vector(0, 0), 0); }, "add_obstacle: radius");
  expect_refused([&] { billiard::stadium(Vector(0, 0), 0, 1); }, "stadium: radius");
  expect_refused([&] { billiard::stadium(Vector(0, 0), 1, -1); }, "stadium: length");
  expect_refused([&] { billiard::stadium(Vector(0, kNever), 1, 1); }, "stadium: centre");
  expect_disc_refused(billiard::stadium(Vector(0, 0), 0.5, 1), disc, "disc 0 at (0, 0) overlaps wall");
  expect_refused([&] { billiard::sinai_billiard(Vector(0, 0), Vector(-1, 1), 0.1); }, "sinai_billiard: upper");
  expect_refused([&] { billiard::sinai_billiard(Vector(-10, -10), Vector(10, 10), 10); }, "sinai_billiard: obstacle_radius");
  // The box fits around the disc, the obstacle does not.
  expect_disc_refused(billiard::sinai_billiard(Vector(-10, -10), Vector(10, 10), 2), disc, "disc 0 at (0, 0) is outside the walls");
  expect_refused([&] { billiard::mushroom(Vector(0, 0), -1, 1, 1); }, "mushroom: cap_radius");
  expect_refused([&] { billiard::mushroom(Vector(0, 0), 5, 10, 1); }, "mushroom: stem_width");
  expect_refused([&] { billiard::mushroom(Vector(0, 0), 5, 2, 0); }, "mushroom: stem_height");
  billiard::Coordinates centres(2, 2);
  centres << 0, 0, 3, 0;
  expect_refused([&] { billiard::union_of_circles(centres, {2}); }, "union_of_circles: radii");
  expect_refused([&] { billiard::union_of_circles(centres, {2, -1}); }, "union_of_circles: circle 1: radius");
  expect_refused([&] { billiard::union_of_circles(billiard::Coordinates(0, 2), {}); }, "union_of_circles: centres");
  billiard::Coordinates twice(2, 2);
  twice << 1, 1, 1, 1;
  expect_refused([&] { billiard::union_of_circles(twice, {2, 2}); }, "coincide");
  // Periodic boxes have no walls.
  billiard::Container periodic = billiard::periodic_box(10, 10);
  expect_refused(periodic, [&] { periodic.add_arc(Vector(5, 5), 1, 0, 1); }, "periodic");
  expect_refused(periodic, [&] { periodic.add_obstacle(Vector(5, 5), 1); }, "periodic");
  expect_refused(periodic, [&] { periodic.add_obstacle(billiard::stadium(Vector(5, 5), 1, 1)); }, "periodic");
  // The container still makes a simulation that runs.
  billiard::Simulation sim(container);
  sim.add_disc(disc);
  EXPECT_EQ(sim.advance(3).collisions, 3);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(ArcWall, FreeArcsUnderGravityWithDiscsPassingTheirGaps) {
  // A cup (lower half circle) and a dome (upper half circle) hanging in a box under gravity:
  // discs fall into the cup through its open top, onto the dome and past the ends of both, so
  // every kind of arc contact happens. Every event is validated; energy to 1e-10 (as the
  // gravity tests).
  billiard::Container container = billiard::box(Vector(-15, -15), Vector(15, 15));
  const int cup = container.add_arc(Vector(0, -4), 6, kPi, 2 * kPi);
  const int dome = container.add_arc(Vector(0, 8), 4, 0, kPi);
  billiard::Simulation sim(container, physics(Vector(0.1, -1)));
  sim.add_random_discs(40, 0.5, 1.0, 4.0, 36);
  const double energy = sim.kinetic_energy() + sim.potential_energy();
  sim.set_validate_every_event(true);
  sim.set_log_events(true);
  const billiard::AdvanceResult result = sim.advance(20000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_FALSE(result.stuck) << result.stuck_reason;
  EXPECT_EQ(result.collisions, 20000);
  EXPECT_NEAR(sim.kinetic_energy() + sim.potential_energy(), energy, 1e-10 * std::abs(energy));
  // Each face of each arc, and the arcs' end points, were hit.
  int inside[2] = {0, 0}, outside[2] = {0, 0}, ends = 0;
  for (const billiard::EventRecord& e : sim.event_log()) {
    if (e.wall == cup || e.wall == dome) {
      const int k = e.wall == cup ? 0 : 1;
      const billiard::WallShape& arc = sim.container().walls()[static_cast<std::size_t>(e.wall)];
      ((e.position - arc.a).norm() < arc.radius ? inside : outside)[k]++;
    } else if (e.wall >= 0 && sim.container().walls()[static_cast<std::size_t>(e.wall)].kind == billiard::WallKind::Point &&
               sim.container().walls()[static_cast<std::size_t>(e.wall)].a.cwiseAbs().maxCoeff() < 15) {
      ++ends;
    }
  }
  EXPECT_GT(inside[0], 0);
  EXPECT_GT(outside[0], 0);
  EXPECT_GT(inside[1], 0);
  EXPECT_GT(outside[1], 0);
  EXPECT_GT(ends, 0);
}

TEST(ArcGeometry, ArcRectangleDistanceAgreesWithDenseSampling) {
  // Random arcs and rectangles: the distance from the points of the arc (20,000 samples) to the
  // rectangle, against the exact formula (end points, corners, extremes, crossings). Sampling
  // overestimates by at most half a sample spacing, radius * pi / 20000.
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-5, 5), angle(-kPi, kPi), sweep(0.1, 2 * kPi), size(0.2, 4);
  const int samples = 20000;
  for (int k = 0; k < 300; ++k) {
    billiard::WallShape arc{billiard::WallKind::Arc, Vector(u(rng), u(rng)), Vector::Zero(), size(rng)};
    arc.start_angle = angle(rng);
    arc.sweep = k % 10 == 0 ? 2 * kPi : sweep(rng);
    const Vector lo(u(rng), u(rng));
    const Vector hi = lo + Vector(size(rng), size(rng));
    double sampled = kNever;
    for (int s = 0; s <= samples; ++s) {
      const Vector p = billiard::arc_point(arc, arc.start_angle + arc.sweep * s / samples);
      sampled = std::min(sampled, billiard::point_rectangle_distance(p, lo, hi));
    }
    const double exact = billiard::arc_rectangle_distance(arc, lo, hi);
    EXPECT_LE(exact, sampled + 1e-12) << "case " << k;
    EXPECT_GE(exact, sampled - arc.radius * kPi / samples - 1e-12) << "case " << k;
  }
}
