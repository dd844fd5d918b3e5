// Instructor-only graded tests of task 4 (`propagate`), hidden from students: they are left out
// of the student release, and the grader shows students neither their names nor their
// feedback (only "hidden test" and its points). They hold out cases a student cannot tune a
// solution to: tables with their own seeds, compared step by step with the independent oracle
// (support/oracle.hpp).
//
// Tolerances as in the visible suite: double against the oracle's long double differs by
// ~1e-15 relative; 1e-9 is ample for rounding and far below any real mistake.
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

namespace {

using billiard::Collision;
using billiard::Coordinates;
using billiard::Velocities;
using billiard::testing::explain;
using billiard::testing::text;

// Compares `steps` steps of the student's propagate with the oracle on one table; stops at the
// first difference (later steps would only repeat it).
void compare_with_oracle(double R, double a, Coordinates c, Velocities v, int steps, const std::string& label) {
  const int n = static_cast<int>(c.rows());
  const double speed = std::sqrt(v.squaredNorm());
  const double scale = a / billiard::testing::max_speed(v);  // time to cross a radius at top speed
  for (int e = 0; e < steps; ++e) {
    const auto expected = billiard::testing::oracle_step(R, a, c, v, 1e-9 * scale);
    Coordinates mine_c = c;
    Velocities mine_v = v;
    Collision got{};
    try {
      got = billiard::testing::recorded_step(billiard::testing::table_board(R, a), mine_c, mine_v,
                                             [&] { return billiard::propagate(R, a, n, mine_c, mine_v); });
    } catch (const std::exception& error) {
      ADD_FAILURE() << explain(text(label, ", step ", e, ": the next collision"),
                               text("propagate threw: ", error.what()), "a valid table must never be refused.");
      return;
    }
    const billiard::testing::OracleEvent* match = nullptr;
    for (const auto& event : expected.events) {
      if (billiard::testing::same_event(event, got)) match = &event;
    }
    const auto& first = expected.events.front();
    if (match == nullptr || !(std::abs(got.time - match->time) <= 1e-9 * (match->time + scale))) {
      ADD_FAILURE() << explain(text(label, ", step ", e, ": ", billiard::testing::describe_event(first.circle, first.other),
                                    " after time ", first.time),
                               text("returned ", billiard::testing::describe_event(got.circle, got.other),
                                    " after time ", got.time),
                               "compare every wall time and every approaching pair's contact time; return the smallest.");
      return;
    }
    const double position_error = (mine_c - match->coordinates).rowwise().norm().maxCoeff();
    const double velocity_error = (mine_v - match->velocities).rowwise().norm().maxCoeff();
    if (!(position_error <= 1e-9 * R) || !(velocity_error <= 1e-9 * speed)) {
      ADD_FAILURE() << explain(text(label, ", step ", e, ": every circle moved by the step and the colliding ones "
                                                         "given their new velocities"),
                               text("positions off by up to ", position_error, ", velocities by up to ", velocity_error),
                               "move every circle by v * t, then change the velocities of the colliding circles only.");
      return;
    }
    // Go on from the oracle's state, so that one mistake never spoils the next steps.
    billiard::testing::oracle_advance(expected, c, v);
  }
}

GRADED_TEST(Propagate, HeldOutTablesMatchTheOracle, 3, hidden) {
  // 24 tables: radius 5 to 60, circle radius 0.2 to 2, area fraction 2% to 30%, 2 to 24
  // circles, Gaussian velocities scaled by 0.1 to 10; 60 steps each.
  std::mt19937_64 rng(0x41dd3eULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 24; ++k) {
    const double R = 5 + 55 * unit(rng);
    const double a = 0.2 + 1.8 * unit(rng);
    const double fraction = 0.02 + 0.28 * unit(rng);
    const int n = std::max(2, std::min(24, static_cast<int>(fraction * R * R / (a * a))));
    const auto seed = static_cast<std::uint64_t>(9000 + k);
    const Coordinates c = billiard::testing::scattered_circles(R, a, n, seed);
    const Velocities v = billiard::testing::gaussian_velocities(n, seed) * std::pow(10.0, 2 * unit(rng) - 1);
    compare_with_oracle(R, a, c, v, 60, text("held-out table ", k, " (R = ", R, ", a = ", a, ", n = ", n, ")"));
  }
}

}  // namespace
