// Stage 5: rough discs, unequal masses and radii, restitution.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <random>

using billiard::Vector;
using engine_test::make_disc;
using engine_test::physics;

namespace {
billiard::Settings exchanging() {
  billiard::Settings settings;
  settings.exchange_velocities = true;
  return settings;
}
}  // namespace

TEST(Rough, UnequalMassesHeadOn) {
  // m = 1 at x = -5 moving +2, m = 3 at rest at x = 5 (radius 1): contact at t = 4; elastic 1D
  // result v1 = (1 - 3) / 4 * 2 = -1, v2 = 2 * 1 / 4 * 2 = 1.
  billiard::Simulation sim(billiard::box(Vector(-20, -20), Vector(20, 20)));
  sim.add_disc(make_disc(Vector(-5, 0), Vector(2, 0), 1.0, 1.0));
  sim.add_disc(make_disc(Vector(5, 0), Vector(0, 0), 1.0, 3.0));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 4.0);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].velocity.x(), -1.0);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].other_velocity.x(), 1.0);
}

TEST(Rough, UnequalRadiiMeetAtTheSumOfRadii) {
  // Radii 0.5 and 2 at x = 0 and x = 10, approaching at relative speed 3: the gap of 7.5 closes
  // at t = 2.5.
  billiard::Simulation sim(billiard::box(Vector(-20, -20), Vector(20, 20)));
  sim.add_disc(make_disc(Vector(0, 0), Vector(1, 0), 0.5));
  sim.add_disc(make_disc(Vector(10, 0), Vector(-2, 0), 2.0));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 2.5);
}

TEST(Rough, InelasticNormalRestitutionLosesTheExpectedEnergy) {
  // Equal masses, e_n = 1/2, head-on at +2 against rest: v1 = (1 - e)/2 * 2 = 0.5,
  // v2 = (1 + e)/2 * 2 = 1.5; kinetic energy 2 -> (0.25 + 2.25) / 2 = 1.25.
  billiard::Simulation sim(billiard::box(Vector(-20, -20), Vector(20, 20)), physics(Vector::Zero(), {0.5, -1.0}));
  sim.add_disc(make_disc(Vector(-5, 0), Vector(2, 0)));
  sim.add_disc(make_disc(Vector(5, 0), Vector(0, 0)));
  sim.advance(1);
  EXPECT_DOUBLE_EQ(sim.kinetic_energy(), 1.25);
}

TEST(Rough, SpinningDiscKicksItselfSidewaysOffAWall) {
  // Uniform disc (m = 1, a = 1, I = 1/2) falling straight onto the floor of a box with spin
  // w = 2 and a perfectly rough contact (e_t = 1). Contact point velocity: v + w a perp(sigma)
  // with sigma = (0, -1): tangential 2 along +x... so g_t = (2, 0); the impulse
  // -(1 + 1) [1 + 2]^-1 g_t = (-4/3, 0) gives vx = -4/3 and spin 2 + 2 (sigma x Q) = 2 - 8/3 = -2/3.
  // The contact point's tangential velocity -4/3 + (-2/3) = -2 is reversed; energy is kept.
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), physics(Vector::Zero(), {1.0, 1.0}));
  billiard::Disc d = make_disc(Vector(10, 5), Vector(0, -1));
  d.spin = 2;
  sim.add_disc(d);
  const double e0 = sim.kinetic_energy();
  sim.advance(1);
  const billiard::State s = sim.current_state();
  EXPECT_NEAR(s.velocities(0, 0), -4.0 / 3, 1e-15);
  EXPECT_NEAR(s.velocities(0, 1), 1.0, 1e-15);
  EXPECT_NEAR(s.spins[0], -2.0 / 3, 1e-15);
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-15);
}

TEST(Rough, PerfectlyRoughMixedDiscsConserveEnergy) {
  // 40 discs, radii 0.5-1.5, masses proportional to area, random spins, e_t = +1 (and the
  // table wall rough too): translational + rotational energy is conserved (1e-12 relative over
  // 50 000 collisions), validate() after every event.
  std::mt19937_64 rng(31);
  billiard::Simulation sim(billiard::circular_table(15), physics(Vector::Zero(), {1.0, 1.0}));
  const auto discs = engine_test::random_discs(rng, 40, 0.5, 1.5, Vector(-15, -15), Vector(15, 15),
                                               [](const Vector& p, double a) { return p.norm() <= 15 - a; });
  std::normal_distribution<double> normal;
  for (std::size_t k = 0; k < discs.positions.size(); ++k) {
    billiard::Disc d = make_disc(discs.positions[k], discs.velocities[k], discs.radii[k], discs.radii[k] * discs.radii[k]);
    d.spin = normal(rng);
    sim.add_disc(d);
  }
  const double e0 = sim.kinetic_energy();
  sim.set_validate_every_event(true);
  const auto result = sim.advance(50000);
  EXPECT_EQ(sim.last_problem(), std::nullopt);
  EXPECT_EQ(result.collisions, 50000);
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-12 * e0);
}

TEST(Rough, CustomInertia) {
  // A ring (I = m a^2) instead of a uniform disc: effective tangential mass [1 + 1]^-1 = 1/2,
  // impulse -(2)(1/2)(2, 0) = (-2, 0): vx = -2, spin 2 + (1)(1)(-2) = 0.
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(20, 20)), physics(Vector::Zero(), {1.0, 1.0}));
  billiard::Disc d = make_disc(Vector(10, 5), Vector(0, -1));
  d.spin = 2;
  d.inertia = 1.0;
  sim.add_disc(d);
  sim.advance(1);
  EXPECT_NEAR(sim.current_state().velocities(0, 0), -2.0, 1e-15);
  EXPECT_NEAR(sim.current_state().spins[0], 0.0, 1e-15);
}

// The exchange rule (Settings::exchange_velocities): discs swap whole velocities, walls
// still reflect only the normal component.
TEST(Exchange, ObliqueEqualDiscsSwapWholeVelocitiesExactly) {
  // Disc 0 at the origin moving (1, 0.5), disc 1 at (3, 0) moving (-1, 0.25): the gap of 1 along
  // x closes at relative speed 2 while y drifts apart by 0.25 t, so they touch before t = 0.5 at
  // an angle; smooth discs would exchange only the normal components.
  billiard::Simulation sim(billiard::box(Vector(-20, -20), Vector(20, 20)), exchanging());
  sim.add_disc(make_disc(Vector(0, 0), Vector(1, 0.5), 1.0));
  sim.add_disc(make_disc(Vector(3, 0), Vector(-1, 0.25), 1.0));
  sim.set_log_events(true);
  sim.advance(1);
  ASSERT_EQ(sim.event_log().size(), 1u);
  const auto& hit = sim.event_log()[0];
  EXPECT_EQ(hit.velocity, Vector(-1, 0.25));  // exactly: a swap, no arithmetic
  EXPECT_EQ(hit.other_velocity, Vector(1, 0.5));
}

TEST(Exchange, WallsStillReflectOnlyTheNormalComponent) {
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)), exchanging());
  sim.add_disc(make_disc(Vector(5, 5), Vector(2, 1), 1.0));
  sim.set_log_events(true);
  sim.advance(1);  // the wall x = 10 at t = 2
  ASSERT_EQ(sim.event_log().size(), 1u);
  EXPECT_DOUBLE_EQ(sim.event_log()[0].time, 2.0);
  EXPECT_EQ(sim.event_log()[0].velocity, Vector(-2, 1));
}

TEST(Exchange, LongRunConservesEnergyAndMomentumInAPeriodicBox) {
  // Swapping velocities conserves both exactly (a permutation), so the sums stay equal to
  // rounding of the sums themselves.
  billiard::Simulation sim(billiard::periodic_box(40, 40), exchanging());
  sim.add_random_discs(200, 1.0, 1.0, 1.0, 7);
  const double energy = sim.kinetic_energy();
  const auto momentum = [&] {
    const auto state = sim.current_state();
    return Vector(state.velocities.col(0).sum(), state.velocities.col(1).sum());
  };
  const Vector start = momentum();
  sim.advance(20000);
  EXPECT_NEAR(sim.kinetic_energy(), energy, 1e-12 * energy);
  EXPECT_LT((momentum() - start).norm(), 1e-10);
  EXPECT_FALSE(sim.validate());
}
