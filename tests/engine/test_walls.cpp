// Stage 3: straight walls with end points, boxes, polygons and the periodic box.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"
#include "wall_geometry.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <random>

using billiard::Vector;
using engine_test::make_disc;

TEST(Walls, CornerHitReversesBothComponentsAtOnce) {
  // Box [0, 10]^2, radius 1 at (5, 5) moving (1, 1): its centre reaches (9, 9) at t = 4, touching
  // the walls x = 10 and y = 10 together. Both hits are processed at t = 4 (two events), leaving
  // velocity (-1, -1); the opposite corner (1, 1) is reached at t = 12.
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)));
  sim.add_disc(make_disc(Vector(5, 5), Vector(1, 1)));
  sim.set_log_events(true);
  sim.set_validate_every_event(true);
  sim.advance(4);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  const auto& log = sim.event_log();
  ASSERT_EQ(log.size(), 4u);
  EXPECT_DOUBLE_EQ(log[0].time, 4.0);
  EXPECT_DOUBLE_EQ(log[1].time, 4.0);
  EXPECT_NE(log[0].wall, log[1].wall);
  EXPECT_DOUBLE_EQ(log[1].velocity.x(), -1.0);
  EXPECT_DOUBLE_EQ(log[1].velocity.y(), -1.0);
  EXPECT_DOUBLE_EQ(log[2].time, 12.0);
  EXPECT_DOUBLE_EQ(log[3].time, 12.0);
}

TEST(Walls, FreeEndOfASegmentIsAnObstacle) {
  // Segment from (0, 0) down to (0, -10) inside a big box. Radius 1 at (-5, 0.6) moving (1, 0)
  // passes above the segment's line but hits its end point (0, 0) when dx^2 + 0.36 = 1: centre
  // at (-0.8, 0.6), t = 4.2. Normal (0.8, -0.6): v' = v - 2 (v.n) n = (1 - 1.28, 0.96).
  billiard::Container room = billiard::box(Vector(-20, -20), Vector(20, 20));
  room.add_segment(Vector(0, 0), Vector(0, -10));
  billiard::Simulation sim(room);
  sim.add_disc(make_disc(Vector(-5, 0.6), Vector(1, 0)));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  const auto& e = sim.event_log()[0];
  EXPECT_NEAR(e.time, 4.2, 1e-14);
  const auto& wall = sim.container().walls()[static_cast<std::size_t>(e.wall)];
  EXPECT_EQ(wall.kind, billiard::WallKind::Point);
  EXPECT_EQ(wall.a, Vector(0, 0));
  EXPECT_NEAR(e.velocity.x(), -0.28, 1e-14);
  EXPECT_NEAR(e.velocity.y(), 0.96, 1e-14);
}

TEST(Walls, DiscBouncesOffBothFacesOfASegment) {
  // Vertical segment x = 0 from y = -5 to 5 in a box [-10, 10]^2; radius 1 at (-4, 0) moving
  // (1, 0) hits its left face at t = 3, then the box wall x = -10 at t = 3 + 8 = 11.
  billiard::Container room = billiard::box(Vector(-10, -10), Vector(10, 10));
  const int segment = room.add_segment(Vector(0, -5), Vector(0, 5));
  billiard::Simulation sim(room);
  sim.add_disc(make_disc(Vector(-4, 0), Vector(1, 0)));
  sim.set_log_events(true);
  sim.advance(2);
  ASSERT_EQ(sim.event_log().size(), 2u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 3.0);
  EXPECT_EQ(sim.event_log()[0].wall, segment);
  EXPECT_DOUBLE_EQ(sim.event_log()[1].time, 11.0);
}

TEST(Walls, RandomRunInsideAConcavePolygonStaysInside) {
  // An L-shaped room (one reflex corner that discs hit as a point): 30 discs, 20 000 collisions,
  // validate() after every event; energy conserved to 1e-12 relative.
  billiard::Coordinates room(6, 2);
  room << 0, 0, 20, 0, 20, 10, 10, 10, 10, 20, 0, 20;
  billiard::Simulation sim(billiard::polygon(room));
  std::mt19937_64 rng(11);
  const auto discs = engine_test::random_discs(rng, 30, 0.4, 1.0, Vector(0, 0), Vector(20, 20), [&](const Vector& p, double a) {
    const bool in = billiard::inside_polygon(room, p);
    double d = 1e9;
    for (int k = 0; k < 6; ++k) d = std::min(d, billiard::distance_to_segment(p, room.row(k), room.row((k + 1) % 6)));
    return in && d >= a;
  });
  engine_test::add_all(sim, discs);
  const double e0 = sim.kinetic_energy();
  sim.set_validate_every_event(true);
  const auto result = sim.advance(20000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_EQ(result.collisions, 20000);
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-12 * e0);
}

TEST(Walls, ManyWallsLiveInTheCells) {
  // A 200-sided polygon (nearly a circle): walls are listed per cell, so a run stays fast and
  // correct. 100 discs, 20 000 collisions, checked at the end and every 1000 events.
  const int sides = 200;
  billiard::Coordinates polygon(sides, 2);
  for (int k = 0; k < sides; ++k) polygon.row(k) << 30 * std::cos(2 * M_PI * k / sides), 30 * std::sin(2 * M_PI * k / sides);
  billiard::Simulation sim(billiard::polygon(polygon));
  std::mt19937_64 rng(12);
  const auto discs = engine_test::random_discs(rng, 100, 1, 1, Vector(-30, -30), Vector(30, 30),
                                               [](const Vector& p, double a) { return p.norm() <= 29.5 - a; });
  engine_test::add_all(sim, discs);
  for (int k = 0; k < 20; ++k) {
    EXPECT_EQ(sim.advance(1000).collisions, 1000);
    ASSERT_EQ(sim.validate(), std::nullopt);
  }
}

TEST(Periodic, DiscWrapsAroundTheBox) {
  // Period 10 x 10; radius 1 at (9.5, 5) moving (1, 0): after 1 time unit it is at (0.5, 5).
  billiard::Simulation sim(billiard::periodic_box(10, 10));
  sim.add_disc(make_disc(Vector(9.5, 5), Vector(1, 0)));
  const auto result = sim.advance(billiard::kAllEvents, 1.0);
  EXPECT_EQ(result.collisions, 0);
  EXPECT_NEAR(sim.current_state().positions(0, 0), 0.5, 1e-14);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Periodic, CollisionAcrossTheBoundary) {
  // Radius 1 at x = 1 and x = 9 in a period of 12 (distance 4 across the boundary, 8 inside);
  // moving apart inside (-1 and +1) they meet through the boundary: gap 2 closes at t = 1.
  billiard::Simulation sim(billiard::periodic_box(12, 12));
  sim.add_disc(make_disc(Vector(1, 6), Vector(-1, 0)));
  sim.add_disc(make_disc(Vector(9, 6), Vector(1, 0)));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 1.0);
  EXPECT_EQ(sim.event_log()[0].kind, billiard::EventKind::DiscDisc);
  EXPECT_EQ(sim.current_state().velocities(0, 0), 1.0);
}

TEST(Periodic, BulkRunConservesEnergyAndMomentum) {
  // The standard bulk system: 400 discs at area fraction ~0.4 in a periodic box, 500 000
  // collisions. No walls, so total momentum is conserved too (to rounding, 1e-11 absolute for
  // speeds of order 1 and 400 discs).
  std::mt19937_64 rng(13);
  const double side = std::sqrt(400 * M_PI / 0.4);
  billiard::Simulation sim(billiard::periodic_box(side, side));
  billiard::Coordinates positions(400, 2), velocities(400, 2);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 400; ++k) {
    positions.row(k) << (k % 20 + 0.5) * side / 20, (k / 20 + 0.5) * side / 20;
    velocities.row(k) << normal(rng), normal(rng);
  }
  sim.add_discs(positions, velocities, 1.0);
  const Vector p0 = sim.current_state().velocities.colwise().sum();
  const double e0 = sim.kinetic_energy();
  const auto result = sim.advance(500000);
  EXPECT_EQ(result.collisions, 500000);
  EXPECT_EQ(result.wall_collisions, 0);
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-12 * e0);
  const Vector p1 = sim.current_state().velocities.colwise().sum();
  EXPECT_NEAR((p1 - p0).norm(), 0.0, 1e-11);
  EXPECT_EQ(sim.validate(), std::nullopt);
}
