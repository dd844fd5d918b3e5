// Periodic image counts (Simulation::images): current_state().positions + images() * period is
// the unwrapped position, continuous in time. Checked against free flight for lone discs (which
// only cross cells), step by step in a gas, through copies, and as zeros without a periodic box.
#include "billiard/engine/simulation.hpp"
#include "helpers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

using billiard::Vector;
using engine_test::make_disc;

namespace {

// Row i of the unwrapped positions of `sim` now.
Vector unwrapped(const billiard::Simulation& sim, int i) {
  const billiard::State state = sim.current_state();
  const billiard::Images images = sim.images();
  const Vector period = sim.container().period();
  return Vector(state.positions(i, 0) + static_cast<double>(images(i, 0)) * period.x(),
              state.positions(i, 1) + static_cast<double>(images(i, 1)) * period.y());
}

}  // namespace

TEST(PeriodicImages, LoneDiscUnwrapsToFreeFlight) {
  // A lone disc meets nothing: it crosses the box many times, right and down, and its unwrapped
  // position is start + v t up to rounding (about 1e-16 of the distance per crossing).
  const Vector period(10, 8);
  const Vector start(3, 2), velocity(7.3, -5.1);
  billiard::Simulation sim(billiard::periodic_box(period.x(), period.y()));
  sim.add_disc(make_disc(start, velocity, 0.5));
  for (int step = 1; step <= 40; ++step) {
    sim.advance(billiard::kAllEvents, 0.37);
    const double t = sim.time();
    const Vector expected = start + t * velocity;
    EXPECT_NEAR((unwrapped(sim, 0) - expected).norm(), 0.0, 1e-12 * expected.norm()) << "at t = " << t;
    // The counts themselves: whole boxes travelled, as floor((start + v t) / period).
    EXPECT_EQ(sim.images()(0, 0), static_cast<std::int64_t>(std::floor(expected.x() / period.x()))) << "at t = " << t;
    EXPECT_EQ(sim.images()(0, 1), static_cast<std::int64_t>(std::floor(expected.y() / period.y()))) << "at t = " << t;
  }
  EXPECT_GE(sim.images()(0, 0), 10);  // 40 x 0.37 x 7.3 / 10 boxes
  EXPECT_LE(sim.images()(0, 1), -8);
}

TEST(PeriodicImages, LoneDiscUnderGravityUnwrapsToAParabola) {
  // Gravity in a periodic box: the disc falls through the box ever faster, up and to the left.
  const Vector period(6, 9);
  const Vector start(1, 4), velocity(-2.5, 6.0), gravity(0.4, -3.0);
  billiard::Settings settings;
  settings.gravity = gravity;
  billiard::Simulation sim(billiard::periodic_box(period.x(), period.y()), settings);
  sim.add_disc(make_disc(start, velocity, 0.5));
  bool rose_a_box = false;
  for (int step = 1; step <= 30; ++step) {
    sim.advance(billiard::kAllEvents, 0.25);
    const double t = sim.time();
    const Vector expected = start + t * velocity + 0.5 * t * t * gravity;
    EXPECT_NEAR((unwrapped(sim, 0) - expected).norm(), 0.0, 1e-11 * (expected.norm() + period.norm()))
        << "at t = " << t;
    EXPECT_EQ(sim.images()(0, 0), static_cast<std::int64_t>(std::floor(expected.x() / period.x()))) << "at t = " << t;
    EXPECT_EQ(sim.images()(0, 1), static_cast<std::int64_t>(std::floor(expected.y() / period.y()))) << "at t = " << t;
    rose_a_box = rose_a_box || sim.images()(0, 1) > 0;
  }
  EXPECT_TRUE(rose_a_box) << "the disc should have crossed the top face on its way up";
  EXPECT_EQ(sim.images()(0, 1), -4);  // y(7.5) = 4 + 45 - 84.375 = -35.375
  EXPECT_EQ(sim.images()(0, 0), -2);  // x(7.5) = 1 - 18.75 + 11.25 = -6.5
}

TEST(PeriodicImages, DiscStartingOnTheLowerFaceMovingOut) {
  // At x = 0 moving left, the disc crosses at once: wrapped near the width, image -1.
  billiard::Simulation sim(billiard::periodic_box(10, 10));
  sim.add_disc(make_disc(Vector(0, 5), Vector(-1, 0), 0.5));
  sim.advance(billiard::kAllEvents, 1e-3);
  EXPECT_EQ(sim.images()(0, 0), -1);
  EXPECT_EQ(sim.images()(0, 1), 0);
  EXPECT_NEAR(sim.current_state().positions(0, 0), 10 - 1e-3, 1e-12);
  EXPECT_NEAR(unwrapped(sim, 0).x(), -1e-3, 1e-12);
}

TEST(PeriodicImages, GasUnwrapsContinuously) {
  // A dilute gas in a small box: between steps short enough that no disc moves a tenth of the
  // box, each unwrapped position moves by at most the largest speed times the step. A wrap
  // counted with the wrong sign, or on the wrong axis, makes a jump of a whole box or two.
  const double side = 12;
  billiard::Simulation sim(billiard::periodic_box(side, side));
  sim.add_random_discs(30, 0.3, 1.0, 1.0, 7);
  const int n = sim.size();
  const double largest_speed = std::sqrt(2 * sim.kinetic_energy());  // (all the energy in one disc of mass 1)
  const double dt = 0.1 * side / largest_speed;
  billiard::State before = sim.current_state();
  billiard::Images images_before = sim.images();
  std::int64_t lowest[2] = {0, 0}, highest[2] = {0, 0};
  for (int step = 0; step < 300; ++step) {
    sim.advance(billiard::kAllEvents, dt);
    const billiard::State now = sim.current_state();
    const billiard::Images images_now = sim.images();
    for (int i = 0; i < n; ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        const double moved = now.positions(i, axis) - before.positions(i, axis) +
                             static_cast<double>(images_now(i, axis) - images_before(i, axis)) * side;
        ASSERT_LE(std::abs(moved), largest_speed * dt * (1 + 1e-9) + 1e-12 * side)
            << "disc " << i << " axis " << axis << " at t = " << sim.time();
        lowest[axis] = std::min(lowest[axis], images_now(i, axis));
        highest[axis] = std::max(highest[axis], images_now(i, axis));
      }
    }
    before = now;
    images_before = images_now;
  }
  ASSERT_EQ(sim.validate(), std::nullopt);
  // The run must have wrapped discs both ways along both axes, or the check above proves little.
  for (int axis = 0; axis < 2; ++axis) {
    EXPECT_LE(lowest[axis], -1) << "axis " << axis;
    EXPECT_GE(highest[axis], 1) << "axis " << axis;
  }
}

TEST(PeriodicImages, CopiesKeepTheirCounts) {
  billiard::Simulation sim(billiard::periodic_box(10, 10));
  sim.add_random_discs(20, 0.4, 1.0, 4.0, 3);
  sim.advance(20000);
  const billiard::Images counted = sim.images();
  ASSERT_GT(counted.cwiseAbs().maxCoeff(), 0);
  billiard::Simulation copy(sim);
  EXPECT_EQ(copy.images(), counted);
  // Both go on the same way; the original's counts are its own.
  sim.advance(5000);
  copy.advance(5000);
  EXPECT_EQ(copy.images(), sim.images());
  EXPECT_EQ(copy.current_state().positions, sim.current_state().positions);
  billiard::Simulation assigned(billiard::periodic_box(10, 10));
  assigned = sim;
  EXPECT_EQ(assigned.images(), sim.images());
}

TEST(PeriodicImages, ZeroWithoutAPeriodicBoxAndBeforeTheFirstAdvance) {
  billiard::Simulation periodic(billiard::periodic_box(10, 10));
  periodic.add_random_discs(5, 0.5, 1.0, 1.0, 1);
  EXPECT_EQ(periodic.images(), billiard::Images::Zero(5, 2));
  billiard::Simulation box(billiard::box(Vector(0, 0), Vector(10, 10)));
  box.add_random_discs(5, 0.5, 1.0, 1.0, 1);
  box.advance(1000);
  EXPECT_EQ(box.images(), billiard::Images::Zero(5, 2));
  billiard::Simulation empty(billiard::periodic_box(10, 10));
  empty.advance(10, 1.0);
  EXPECT_EQ(empty.images().rows(), 0);
}
