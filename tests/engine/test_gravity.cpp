// Stage 2: uniform gravity. Free fall and bounces with known times, the quartic circular wall,
// and conservation of kinetic plus potential energy.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"
#include "wall_geometry.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <random>

using billiard::Vector;
using engine_test::make_disc;
using engine_test::physics;

namespace {
}  // namespace

TEST(Gravity, FreeFallOntoAFloorBouncesEveryTwoVOverG) {
  // Box [0, 100]^2, g = 10 downwards, radius 1 released at rest with its lowest point 20 above the
  // floor: lands at t = sqrt(2 h / g) = 2 with speed v = g t = 20, and (elastic) bounces back to
  // the same height: landings every 2 v / g = 4, at 2, 6, 10, 14, 18. The disc meets the floor
  // kFixedContactSlack radii lower than touching (h = 20 + 1e-10), which shifts those times by
  // 5e-12 per landing: the test includes it. Tolerance 1e-12: rounding of the quadratic roots
  // accumulates over the bounces.
  const double h = 20 + billiard::kFixedContactSlack;
  const double v = std::sqrt(2 * 10 * h);
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(100, 100)), physics(Vector(0, -10)));
  sim.add_disc(make_disc(Vector(50, 21), Vector(0, 0)));
  sim.set_log_events(true);
  sim.advance(5);
  ASSERT_EQ(sim.event_log().size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(sim.event_log()[k].time, (v + 2 * v * k) / 10, 1e-12) << "bounce " << k;
    EXPECT_NEAR(sim.event_log()[k].velocity.y(), 20.0, 1e-10);
  }
}

TEST(Gravity, DiscDroppedInTheCircularTable) {
  // Table R = 10, radius 1, released at rest at the centre with g = 2 downwards: reaches the
  // rim (reach 9) at t = sqrt(2 * 9 / 2) = 3, bounces straight up, is back at the centre at rest
  // at t = 6 and lands again at t = 9: landings every 6. With the fixed contact slack the reach is
  // 9 + 1e-10: t = sqrt(reach), every 2 sqrt(reach).
  const double reach = 9 + billiard::kFixedContactSlack;
  billiard::Simulation sim(billiard::circular_table(10), physics(Vector(0, -2)));
  sim.add_disc(make_disc(Vector(0, 0), Vector(0, 0)));
  sim.set_log_events(true);
  sim.advance(3);
  ASSERT_EQ(sim.event_log().size(), 3u);
  EXPECT_NEAR(sim.event_log()[0].time, std::sqrt(reach), 1e-12);
  EXPECT_NEAR(sim.event_log()[1].time, 3 * std::sqrt(reach), 1e-11);
  EXPECT_NEAR(sim.event_log()[2].time, 5 * std::sqrt(reach), 1e-11);
  EXPECT_NEAR(sim.event_log()[0].position.y(), -reach, 1e-11);
}

TEST(Gravity, SidewaysGravityAnyDirection) {
  // Gravity along +x of 8: from rest at x = 5 in the box [0, 20]^2 (radius 1), the wall x = 20 is
  // reached when 14 = 4 t^2: t = sqrt(3.5) (14 + 1e-10 with the fixed contact slack).
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), physics(Vector(8, 0)));
  sim.add_disc(make_disc(Vector(5, 10), Vector(0, 0)));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  EXPECT_NEAR(sim.event_log()[0].time, std::sqrt((14 + billiard::kFixedContactSlack) / 4), 1e-13);
}

namespace {
void random_gravity_run(billiard::Simulation& sim, int n, std::int64_t events, std::uint64_t seed, const Vector& lo,
                        const Vector& hi, bool table, double table_radius) {
  std::mt19937_64 rng(seed);
  const auto discs = engine_test::random_discs(rng, n, 0.5, 1.0, lo, hi, [&](const Vector& p, double a) {
    if (table) return p.norm() <= table_radius - a;
    return p.x() >= lo.x() + a && p.x() <= hi.x() - a && p.y() >= lo.y() + a && p.y() <= hi.y() - a;
  });
  engine_test::add_all(sim, discs);
  const double e0 = sim.kinetic_energy() + sim.potential_energy();
  sim.set_validate_every_event(true);
  const auto result = sim.advance(events);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_FALSE(result.stuck);
  EXPECT_EQ(result.collisions, events);
  // Kinetic plus potential energy: conserved to rounding. Positions enter the potential, so
  // the rounding walk is larger than without gravity: 1e-10 relative.
  const double e1 = sim.kinetic_energy() + sim.potential_energy();
  EXPECT_NEAR(e1, e0, 1e-10 * std::abs(e0));
}
}  // namespace

TEST(Gravity, RandomRunInABoxKeepsEnergyAndNeverOverlaps) {
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), physics(Vector(0.3, -1)));
  random_gravity_run(sim, 40, 20000, 21, Vector(0, 0), Vector(20, 20), false, 0);
}

TEST(Gravity, RandomRunInTheTableKeepsEnergyAndNeverOverlaps) {
  billiard::Simulation sim(billiard::circular_table(12), physics(Vector(0, -1)));
  random_gravity_run(sim, 40, 20000, 22, Vector(-12, -12), Vector(12, 12), true, 12);
}

TEST(Gravity, RandomRunWithPolygonCornersAndFreeEnds) {
  // A funnel: segment end points meet the discs under gravity (quartic disc-point times).
  billiard::Container funnel = billiard::box(Vector(0, 0), Vector(30, 30));
  funnel.add_segment(Vector(3, 15), Vector(13, 10));
  funnel.add_segment(Vector(27, 15), Vector(17, 10));
  billiard::Simulation sim(funnel, physics(Vector(0, -1)));
  std::mt19937_64 rng(23);
  const auto discs = engine_test::random_discs(rng, 30, 0.5, 1.0, Vector(0, 0), Vector(30, 30), [&](const Vector& p, double a) {
    return p.x() >= a && p.x() <= 30 - a && p.y() >= a && p.y() <= 30 - a &&
           billiard::distance_to_segment(p, Vector(3, 15), Vector(13, 10)) >= a &&
           billiard::distance_to_segment(p, Vector(27, 15), Vector(17, 10)) >= a;
  });
  engine_test::add_all(sim, discs);
  const double e0 = sim.kinetic_energy() + sim.potential_energy();
  sim.set_validate_every_event(true);
  const auto result = sim.advance(20000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_EQ(result.collisions, 20000);
  EXPECT_NEAR(sim.kinetic_energy() + sim.potential_energy(), e0, 1e-10 * std::abs(e0));
}
