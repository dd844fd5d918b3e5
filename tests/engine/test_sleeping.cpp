// Discs at rest under gravity: the fixed contact slack (a disc resting or sliding on a floor
// hops instead of stalling), sleeping discs (a slow disc held up falls asleep; a slow hit bounces
// off a sleeper, a fast one wakes it), and the hard case for sleeping: a box whose rows of discs
// fill it exactly, which used to cost ever more collisions per unit of time.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <cstdio>
#include <vector>

using billiard::EventKind;
using billiard::kAllEvents;
using billiard::Vector;
using engine_test::make_disc;

namespace {

double total_energy(const billiard::Simulation& sim) { return sim.kinetic_energy() + sim.potential_energy(); }

// The box (0,0)-(40,40) under gravity (0, -1), restitution e.
billiard::Simulation falling(double restitution) {
  billiard::Settings settings;
  settings.gravity = Vector(0, -1);
  settings.restitution.normal = restitution;
  return billiard::Simulation(billiard::box(Vector(0, 0), Vector(40, 40)), settings);
}

// One disc of radius 1 in that box.
billiard::Simulation one_disc(const Vector& position, const Vector& velocity, double restitution) {
  billiard::Simulation sim = falling(restitution);
  sim.add_disc(make_disc(position, velocity));
  return sim;
}

}  // namespace

TEST(Sleeping, DiscAtRestOnAFloorHopsAtTheSlackScale) {
  // Elastic (no sleeping): a disc released at rest touching the floor drops the slack,
  // s = 1e-10 radii, and bounces back up as high: one landing every 2 sqrt(2 s / g) = 2.83e-5,
  // the first after half of that. Before the slack it met the floor again at once, for ever.
  billiard::Simulation sim = one_disc(Vector(20, 1), Vector(0, 0), 1.0);
  const double period = 2 * std::sqrt(2 * billiard::kFixedContactSlack);
  const double duration = 0.01;
  const billiard::AdvanceResult r = sim.advance(kAllEvents, duration);
  ASSERT_FALSE(r.stuck) << r.stuck_reason;
  EXPECT_EQ(sim.time(), duration);
  const double landings = std::floor((duration - period / 2) / period) + 1;
  EXPECT_NEAR(static_cast<double>(r.wall_collisions), landings, 1.0);
  EXPECT_NEAR(total_energy(sim), 1.0, 1e-12);  // potential -m g.r = 1 at height 1, at rest
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Sleeping, DiscSlidingAlongAFloorReachesTheWall) {
  // Elastic: sliding at speed 1 along the floor from x = 20, the disc reaches the wall x = 40 at
  // x = 39 (less the slack) at t = 19, hopping at the slack scale on the way (it used to stall
  // at t = 0). Tolerance 1e-6: its hops add nothing to its horizontal motion.
  billiard::Simulation sim = one_disc(Vector(20, 1), Vector(1, 0), 1.0);
  sim.set_log_events(true);
  double hit = -1;
  while (hit < 0 && sim.time() < 20) {
    const billiard::AdvanceResult r = sim.advance(100000, 20.0 - sim.time());
    ASSERT_FALSE(r.stuck) << r.stuck_reason;
    for (const billiard::EventRecord& e : sim.event_log()) {
      if (hit < 0 && e.kind == EventKind::DiscWall && e.velocity.x() < 0) hit = e.time;
    }
    sim.clear_event_log();
  }
  EXPECT_NEAR(hit, 19.0, 1e-6);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Sleeping, BouncingDiscComesToRestAndFallsAsleep) {
  // Restitution 0.5, dropped from 1 above the floor: the bounces die out, and the disc, held up by
  // the floor and slower than the sleep speed sqrt(2 g 0.05 a) for 3 v / g, falls asleep: it stops
  // where it is (no higher than the island gap, a tenth of its radius, above the floor) and costs
  // no events from then on. Its energy only ever went down.
  billiard::Simulation sim = one_disc(Vector(20, 2), Vector(0, 0), 0.5);
  sim.set_log_events(true);
  double energy = total_energy(sim);
  for (int step = 0; step < 10; ++step) {
    const billiard::AdvanceResult r = sim.advance(kAllEvents, 1.0);
    ASSERT_FALSE(r.stuck) << r.stuck_reason;
    ASSERT_LE(total_energy(sim), energy + 1e-12);
    energy = total_energy(sim);
  }
  EXPECT_EQ(sim.sleep_speed(), std::sqrt(2 * billiard::kRestingBounce));
  ASSERT_EQ(sim.sleeping_discs(), std::vector<int>{0});
  const billiard::State s = sim.current_state();
  EXPECT_EQ(s.velocities(0, 1), 0.0);
  EXPECT_GE(s.positions(0, 1), 1.0 - 1e-9);
  EXPECT_LE(s.positions(0, 1), 1.1);
  EXPECT_EQ(sim.event_log().back().kind, EventKind::Sleep);
  EXPECT_EQ(sim.advance(kAllEvents, 10.0).collisions, 0);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

namespace {

// Disc A at rest on the floor at x = 10 falls asleep within a few time units; disc B, 0.5 above
// it, is thrown straight up at speed 2 and comes down on top of A at t = 2 + sqrt(5) (where
// 3.5 + 2 t - t^2 / 2 = 3) at speed sqrt(5). Runs to just before that and returns the simulation.
billiard::Simulation disc_thrown_onto_a_sleeper() {
  billiard::Simulation sim = falling(0.5);
  sim.add_disc(make_disc(Vector(10, 1), Vector(0, 0)));
  sim.add_disc(make_disc(Vector(10, 3.5), Vector(0, 2)));
  sim.set_log_events(true);
  sim.advance(kAllEvents, 4.0);
  return sim;
}

}  // namespace

TEST(Sleeping, SlowHitBouncesOffASleeperWhichStaysPut) {
  // With the sleep speed raised to 5 (the sleeper stays asleep), B's hit at sqrt(5) is slow: A is
  // an immovable body, B bounces straight back up at half its speed, and A has not moved at all.
  billiard::Simulation sim = disc_thrown_onto_a_sleeper();
  ASSERT_EQ(sim.sleeping_discs(), std::vector<int>{0});
  const Vector rest = sim.current_state().positions.row(0);
  sim.set_sleep_speed(5.0);
  sim.clear_event_log();
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  const billiard::EventRecord& hit = sim.event_log()[0];
  EXPECT_EQ(hit.kind, EventKind::DiscDisc);
  EXPECT_NEAR(hit.time, 2 + std::sqrt(5.0), 1e-9);
  const int b = hit.disc == 1 ? 0 : 1;  // (which side the record calls `disc`)
  const Vector velocity_b = b == 0 ? hit.velocity : hit.other_velocity;
  EXPECT_NEAR(velocity_b.y(), 0.5 * std::sqrt(5.0), 1e-9);
  EXPECT_EQ(sim.sleeping_discs(), std::vector<int>{0});
  const Vector after = sim.current_state().positions.row(0);
  EXPECT_EQ(after, rest);
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Sleeping, FastHitWakesTheSleeper) {
  // At the default sleep speed (0.32), the same hit at sqrt(5) wakes A: a Wake record, then an
  // ordinary collision of equal masses with restitution 0.5: B keeps (1 - e) / 2 of its velocity
  // and A takes (1 + e) / 2, downwards into the floor.
  billiard::Simulation sim = disc_thrown_onto_a_sleeper();
  ASSERT_EQ(sim.sleeping_discs(), std::vector<int>{0});
  sim.clear_event_log();
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 2u);
  EXPECT_EQ(sim.event_log()[0].kind, EventKind::Wake);
  EXPECT_EQ(sim.event_log()[0].disc, 0);
  const billiard::EventRecord& hit = sim.event_log()[1];
  EXPECT_EQ(hit.kind, EventKind::DiscDisc);
  EXPECT_NEAR(hit.time, 2 + std::sqrt(5.0), 1e-9);
  const Vector velocity_a = hit.disc == 0 ? hit.velocity : hit.other_velocity;
  const Vector velocity_b = hit.disc == 0 ? hit.other_velocity : hit.velocity;
  EXPECT_NEAR(velocity_a.y(), -0.75 * std::sqrt(5.0), 1e-9);
  EXPECT_NEAR(velocity_b.y(), -0.25 * std::sqrt(5.0), 1e-9);
  EXPECT_TRUE(sim.sleeping_discs().empty());
  // Both come to rest again and fall asleep.
  sim.advance(kAllEvents, 20.0);
  EXPECT_EQ(sim.sleeping_discs(), (std::vector<int>{0, 1}));
  EXPECT_EQ(sim.validate(), std::nullopt);
}

TEST(Sleeping, SleepSpeedZeroWakesEveryDiscAndRefusesBadValues) {
  billiard::Simulation sim = disc_thrown_onto_a_sleeper();
  ASSERT_EQ(sim.sleeping_discs(), std::vector<int>{0});
  for (const double bad : {-1.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(sim.set_sleep_speed(bad), std::invalid_argument);
  }
  EXPECT_EQ(sim.sleeping_discs(), std::vector<int>{0});  // unchanged by the refusals
  sim.set_sleep_speed(0.0);
  EXPECT_TRUE(sim.sleeping_discs().empty());
  EXPECT_EQ(sim.event_log().back().kind, EventKind::Wake);
  EXPECT_EQ(sim.validate(), std::nullopt);
  // Elastic discs do not sleep by default; no gravity, never.
  billiard::Simulation elastic = one_disc(Vector(20, 1), Vector(0, 0), 1.0);
  elastic.advance(10);
  EXPECT_EQ(elastic.sleep_speed(), 0.0);
  billiard::Settings inelastic;
  inelastic.restitution.normal = 0.5;
  inelastic.sleep_speed = 1.0;
  billiard::Simulation weightless(billiard::periodic_box(20, 20), inelastic);
  weightless.add_random_discs(10, 1.0, 1.0, 1.0, 1);
  weightless.advance(10);
  EXPECT_EQ(weightless.sleep_speed(), 0.0);
}

namespace {

// The hard case: 200 discs of radius 1 in the box (0,0)-(40,40), which rows of 20 fill
// exactly, g = (0, -1), seed 7. Without sleeping its bottom row's sideways rattling cost ever more
// (restitution 0.5: 204, 738, 1153, ... 2282 collisions per disc per unit time in successive
// quarters of t = 0..200). Now: to t = 200 with every collision's discs checked, the energy never
// rising, and no collision at all in the last quarter.
void exactly_filled_box_falls_asleep(double restitution) {
  billiard::Simulation sim = falling(restitution);
  sim.add_random_discs(200, 1.0, 1.0, 1.0, 7);
  sim.set_check_event_discs(true);
  double energy = total_energy(sim);
  const double tolerance = 1e-12 * std::abs(energy);
  std::vector<long long> per_quarter;
  for (int quarter = 0; quarter < 8; ++quarter) {
    long long collisions = 0;
    for (int step = 0; step < 25; ++step) {
      const billiard::AdvanceResult r = sim.advance(kAllEvents, 1.0);
      ASSERT_FALSE(r.stuck) << r.stuck_reason;
      ASSERT_EQ(sim.last_problem(), std::nullopt) << "at time " << sim.time();
      ASSERT_LE(total_energy(sim), energy + tolerance) << "the energy rose at time " << sim.time();
      energy = total_energy(sim);
      collisions += r.collisions;
    }
    per_quarter.push_back(collisions / 200 / 25);
  }
  EXPECT_NEAR(sim.time(), 200.0, 1e-9);
  EXPECT_EQ(per_quarter.back(), 0);
  EXPECT_EQ(sim.sleeping_discs().size(), 200u);
  EXPECT_EQ(sim.validate(), std::nullopt);
  std::printf("box 40 x 40, 200 discs, e = %.2f: collisions per disc per unit time by quarter:", restitution);
  for (long long rate : per_quarter) std::printf(" %lld", rate);
  std::printf("\n");
}

}  // namespace

// The livelier boxes take several seconds each: with the long runs (label stress).
TEST(Sleeping, ExactlyFilledBoxFallsAsleepRestitution50) { exactly_filled_box_falls_asleep(0.5); }
TEST(Sleeping, StressExactlyFilledBoxFallsAsleepRestitution80) { exactly_filled_box_falls_asleep(0.8); }
TEST(Sleeping, StressExactlyFilledBoxFallsAsleepRestitution95) { exactly_filled_box_falls_asleep(0.95); }
