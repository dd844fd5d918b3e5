// The long run: 10^8 collisions at N = 10 000 (area fraction 0.5, periodic
// box) with no overlap and no stuck event. Label "stress" (left out of the default run): 75 s in
// Release here (66 s without the per-collision checks). After every collision the discs it
// changed are checked against every disc near them (set_check_event_discs: inside, in their
// cells, no overlap beyond 1e-9 of a radius, next event not in the past); every 10^7 collisions
// the whole system with validate() (which also checks the queue); and energy at the end.
#include "billiard/engine/simulation.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <cmath>
#include <random>

TEST(StressEngine, HundredMillionCollisionsAtTenThousandDiscs) {
  const int n = 10000;
  const double side = std::sqrt(n * M_PI / 0.5);
  billiard::Simulation sim(billiard::periodic_box(side, side));
  billiard::Coordinates positions(n, 2), velocities(n, 2);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int k = 0; k < n; ++k) {
    positions.row(k) << (k % 100 + 0.5) * side / 100, (k / 100 + 0.5) * side / 100;
    velocities.row(k) << normal(rng), normal(rng);
  }
  sim.add_discs(positions, velocities, 1.0);
  sim.set_check_event_discs(true);
  const double e0 = sim.kinetic_energy();
  for (int round = 0; round < 10; ++round) {
    const auto result = sim.advance(10000000);
    ASSERT_EQ(sim.last_problem(), std::nullopt) << "in block " << (round + 1) << " of 10 (10 million collisions each)";
    ASSERT_FALSE(result.stuck);
    ASSERT_EQ(result.collisions, 10000000);
    ASSERT_EQ(sim.validate(), std::nullopt) << "after " << (round + 1) << "0 million collisions";
  }
  // 10^8 collisions: random walk of ~1e-16 sqrt(10^8) = 1e-12; allow 1e-10 (1e-12 per 10^6).
  EXPECT_NEAR(sim.kinetic_energy(), e0, 1e-10 * e0);
}
