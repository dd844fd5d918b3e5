// Stage 1: smooth discs on the circular table. Hand-checkable bounces, the conservation laws,
// no overlap after every event, and the same first events as the course's all-pairs propagate.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#ifdef BILLIARD_HAVE_COURSE_SOLUTIONS
#include "billiard/course.hpp"
#endif

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <type_traits>

// One name per meaning (billiard/vectors.hpp): what the engine takes and returns is what a
// course function takes and returns, rows and all, with no conversion between them.
static_assert(std::is_same_v<decltype(billiard::State::positions), billiard::Coordinates>);
static_assert(std::is_same_v<decltype(billiard::State::velocities), billiard::Velocities>);
static_assert(std::is_same_v<decltype(billiard::Disc::position), billiard::Vector>);
static_assert(std::is_same_v<std::decay_t<decltype(billiard::Coordinates().row(0).eval())>, billiard::Vector>);

using billiard::Vector;
using engine_test::make_disc;

namespace {
billiard::Simulation random_table(std::mt19937_64& rng, int n, double table, double radius_lo, double radius_hi) {
  billiard::Simulation sim(billiard::circular_table(table));
  const auto discs = engine_test::random_discs(rng, n, radius_lo, radius_hi, Vector(-table, -table), Vector(table, table),
                                               [&](const Vector& p, double a) { return p.norm() <= table - a; });
  engine_test::add_all(sim, discs);
  return sim;
}
}  // namespace

TEST(Table, OneDiscBouncesAcrossTheCentre) {
  // R = 10, a = 1, from the centre at speed 2: the rim (reach 9) at t = 4.5, then a diameter
  // (18) every 9 time units: 4.5, 13.5, 22.5. Exact in binary: compared with EXPECT_DOUBLE_EQ.
  billiard::Simulation sim(billiard::circular_table(10));
  sim.add_disc(make_disc(Vector(0, 0), Vector(2, 0)));
  sim.set_log_events(true);
  const auto result = sim.advance(3);
  EXPECT_EQ(result.collisions, 3);
  ASSERT_EQ(sim.event_log().size(), 3u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 4.5);
  EXPECT_DOUBLE_EQ(sim.event_log()[1].time, 13.5);
  EXPECT_DOUBLE_EQ(sim.event_log()[2].time, 22.5);
  EXPECT_EQ(sim.event_log()[0].other, billiard::kWall);
  EXPECT_DOUBLE_EQ(sim.current_state().velocities(0, 0), -2.0);  // three reflections of +2
}

TEST(Table, TwoDiscsHeadOn) {
  // Radius 1 at x = -5 and 5, speeds +1 and -1: touch at t = 4 (gap 8 at relative speed 2)
  // and exchange velocities; then each reaches the rim (reach 9) from |x| = 1 at t = 4 + 8 = 12.
  billiard::Simulation sim(billiard::circular_table(10));
  sim.add_disc(make_disc(Vector(-5, 0), Vector(1, 0)));
  sim.add_disc(make_disc(Vector(5, 0), Vector(-1, 0)));
  sim.set_log_events(true);
  sim.advance(3);
  const auto& log = sim.event_log();
  ASSERT_EQ(log.size(), 3u);
  EXPECT_DOUBLE_EQ(log[0].time, 4.0);
  EXPECT_EQ(log[0].kind, billiard::EventKind::DiscDisc);
  EXPECT_DOUBLE_EQ(log[1].time, 12.0);
  EXPECT_DOUBLE_EQ(log[2].time, 12.0);
  EXPECT_EQ(log[1].kind, billiard::EventKind::DiscWall);
}

TEST(Table, DiscAtRestNeverCollides) {
  billiard::Simulation sim(billiard::circular_table(5));
  sim.add_disc(make_disc(Vector(1, 2), Vector(0, 0)));
  const auto result = sim.advance(10, 7.5);
  EXPECT_EQ(result.collisions, 0);
  EXPECT_FALSE(result.stuck);
  EXPECT_DOUBLE_EQ(sim.time(), 7.5);
  EXPECT_EQ(sim.current_state().positions(0, 1), 2.0);
  // With an unlimited duration there is nothing to wait for: the clock stays.
  sim.advance(10);
  EXPECT_DOUBLE_EQ(sim.time(), 7.5);
}

TEST(Table, NoOverlapAfterEveryEventOfALongRandomRun) {
  // 40 discs of mixed radii, 30 000 collisions, validate() after each one: no overlap beyond
  // 1e-9 of a radius, every disc inside the table and in its cell, the queue in heap order.
  std::mt19937_64 rng(1);
  billiard::Simulation sim = random_table(rng, 40, 12, 0.5, 1.2);
  sim.set_validate_every_event(true);
  const auto result = sim.advance(30000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_EQ(result.collisions, 30000);
}

TEST(Table, EnergyAndAngularMomentumAreConserved) {
  // 200 equal discs, 10^6 collisions. Rounding makes a random walk of ~1e-16 per event, so
  // after 10^6 events about 1e-13 relative; the bound is 1e-12 per million events. The
  // angular momentum about the centre is conserved by wall hits (normal through the centre) and
  // by disc collisions; its rounding walk is larger (positions enter): 1e-9 relative.
  std::mt19937_64 rng(2);
  billiard::Simulation sim = random_table(rng, 200, 30, 1, 1);
  const double e0 = sim.kinetic_energy();
  const double l0 = engine_test::angular_momentum(sim.current_state());
  const auto result = sim.advance(1000000);
  EXPECT_EQ(result.collisions, 1000000);
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-12 * e0);
  const double l1 = engine_test::angular_momentum(sim.current_state());
  EXPECT_NEAR(l1, l0, 1e-9 * std::max(1.0, std::abs(l0)));
  EXPECT_EQ(sim.validate(), std::nullopt);
}

#ifdef BILLIARD_HAVE_COURSE_SOLUTIONS
TEST(Table, SameFirstTwentyEventsAsTheCoursePropagate) {
  // 60 random small systems (2 to 12 equal discs, radius 0.3 to 1.5, table 10): the course's
  // all-pairs propagate and the engine must report the same 20 collisions (same discs, same
  // times to 1e-9; the two codes round differently, so times agree to ~1e-13, not exactly).
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> count(2, 12);
  std::uniform_real_distribution<double> radius(0.3, 1.5);
  for (int system = 0; system < 60; ++system) {
    const int n = count(rng);
    const double a = radius(rng);
    const double table = 10;
    const auto discs = engine_test::random_discs(rng, n, a, a, Vector(-table, -table), Vector(table, table),
                                                 [&](const Vector& p, double r) { return p.norm() <= table - r; });
    billiard::Coordinates coordinates(n, 2);
    billiard::Velocities velocities(n, 2);
    billiard::Simulation sim(billiard::circular_table(table));
    for (int i = 0; i < n; ++i) {
      coordinates.row(i) = discs.positions[i];
      velocities.row(i) = discs.velocities[i];
      sim.add_disc(make_disc(discs.positions[i], discs.velocities[i], a));
    }
    sim.set_log_events(true);
    sim.advance(20);
    ASSERT_EQ(sim.event_log().size(), 20u);
    double time = 0;
    for (int k = 0; k < 20; ++k) {
      const billiard::Collision c = billiard::propagate(table, a, n, coordinates, velocities);
      time += c.time;
      const billiard::EventRecord& e = sim.event_log()[k];
      const int lo = e.other == billiard::kWall ? e.disc : std::min(e.disc, e.other);
      const int hi = e.other == billiard::kWall ? billiard::kWall : std::max(e.disc, e.other);
      const int course_lo = c.other == billiard::kWall ? c.circle : std::min(c.circle, c.other);
      const int course_hi = c.other == billiard::kWall ? billiard::kWall : std::max(c.circle, c.other);
      ASSERT_EQ(lo, course_lo) << "system " << system << ", event " << k;
      ASSERT_EQ(hi, course_hi) << "system " << system << ", event " << k;
      ASSERT_NEAR(e.time, time, 1e-9) << "system " << system << ", event " << k;
    }
  }
}
#endif
