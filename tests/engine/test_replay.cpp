// Replay (billiard/engine/replay.hpp): walking a recorded run forward event by event and at fixed
// time steps gives states without overlaps that end at the live run's state, and a new Replay
// for each time agrees with one Replay walked forward. Tolerance 1e-12: the states are
// extrapolated from different records, so they differ by rounding only.
#include "billiard/engine/replay.hpp"

#include "helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace {

using billiard::Vector;

double largest_difference(const billiard::State& a, const billiard::State& b) {
  return std::max((a.positions - b.positions).cwiseAbs().maxCoeff(), (a.velocities - b.velocities).cwiseAbs().maxCoeff());
}

billiard::Simulation logged_run(bool periodic) {
  std::mt19937_64 rng(periodic ? 7 : 8);
  billiard::Settings settings;
  if (!periodic) settings.gravity = Vector(0.1, -0.3);
  billiard::Simulation sim(periodic ? billiard::periodic_box(20, 20) : billiard::box(Vector(0, 0), Vector(20, 20)), settings);
  const auto discs = engine_test::random_discs(rng, 25, 0.5, 1.0, Vector(0, 0), Vector(20, 20), [](const Vector& p, double a) {
    return p.x() >= a && p.x() <= 20 - a && p.y() >= a && p.y() <= 20 - a;
  });
  engine_test::add_all(sim, discs);
  sim.set_log_events(true);
  sim.advance(300);
  return sim;
}

TEST(Replay, EventByEventMatchesTheLogAndEndsAtTheLiveState) {
  for (const bool periodic : {false, true}) {
    const billiard::Simulation sim = logged_run(periodic);
    billiard::Replay replay(sim);
    std::size_t k = 0;
    const Eigen::VectorXd radii = sim.radii();
    double previous = 0;
    while (!replay.finished()) {
      const billiard::State s = replay.after_next_event();
      // At its logged time, and (replayed free flight being right) no two discs overlap.
      ASSERT_EQ(s.time, sim.event_log()[k].time) << "event " << k;
      ASSERT_GE(s.time, previous);
      previous = s.time;
      for (int i = 0; i < s.positions.rows(); ++i) {
        for (int j = i + 1; j < s.positions.rows(); ++j) {
          Vector d = (s.positions.row(i) - s.positions.row(j));
          if (periodic) d -= Vector(20 * std::round(d.x() / 20), 20 * std::round(d.y() / 20));
          ASSERT_GE(d.norm(), radii[i] + radii[j] - 1e-9) << "event " << k << ": discs " << i << ", " << j;
        }
      }
      ++k;
    }
    EXPECT_EQ(k, sim.event_log().size());
    EXPECT_EQ(replay.applied(), k);
    EXPECT_LT(largest_difference(replay.at(sim.time()), sim.current_state()), 1e-12);
    EXPECT_THROW(replay.after_next_event(), std::logic_error);
  }
}

TEST(Replay, FixedTimeStepsMatchReplayAt) {
  const billiard::Simulation sim = logged_run(false);
  billiard::Replay replay(sim);
  int frames = 0;
  for (double t = 0; t <= sim.time(); t += 0.05, ++frames) {
    ASSERT_LT(largest_difference(replay.at(t), billiard::Replay(sim).at(t)), 1e-12) << "t = " << t;
  }
  EXPECT_GT(frames, 10);
  // Time may not go back.
  EXPECT_THROW(replay.at(0.0), std::invalid_argument);
}

TEST(Replay, ATwoDiscHeadOnRunByHand) {
  // Discs of radius 1 at x = 2 and 8 (y = 5) in a 10 x 10 box, approaching at speed 1 each:
  // contact at t = 2 (gap 6 - 2 = 4 closed at relative speed 2), then they fly back and hit
  // the walls at t = 2 + 4 = 6 (x = 1 and 9).
  billiard::Simulation sim(billiard::box(Vector(0, 0), Vector(10, 10)));
  billiard::Disc a;
  a.position = Vector(2, 5);
  a.velocity = Vector(1, 0);
  billiard::Disc b = a;
  b.position = Vector(8, 5);
  b.velocity = Vector(-1, 0);
  sim.add_disc(a);
  sim.add_disc(b);
  sim.set_log_events(true);
  sim.advance(3);
  billiard::Replay replay(sim);
  const billiard::State first = replay.after_next_event();
  EXPECT_NEAR(first.time, 2.0, 1e-12);
  EXPECT_NEAR(first.positions(0, 0), 4.0, 1e-12);
  EXPECT_NEAR(first.velocities(0, 0), -1.0, 1e-12);
  const billiard::State mid = replay.at(4.0);  // flying apart: x = 2 and 8 again
  EXPECT_NEAR(mid.positions(0, 0), 2.0, 1e-12);
  EXPECT_NEAR(mid.positions(1, 0), 8.0, 1e-12);
  const billiard::State walls = replay.at(6.0);  // both walls hit at t = 6 (logged)
  EXPECT_EQ(replay.applied(), 3u);
  EXPECT_NEAR(walls.velocities(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(walls.velocities(1, 0), -1.0, 1e-12);
}

}  // namespace
