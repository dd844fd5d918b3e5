// Helpers shared by the graded suite of task 9 (sectors) and its hidden tests: one step of the
// student's propagate_sectors compared with the independent oracle (support/oracle.hpp) from
// the same state.
//
// Tolerances: the student's double arithmetic and the oracle's long double differ by rounding
// only, ~1e-15 relative per step; 1e-9 (of the time scale, of R, of the speed) is ample for
// that and far below any real mistake. Events within 1e-9 of a time scale of the earliest one
// are ties: any of them is right.
#pragma once

#include "billiard/extensions.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

namespace billiard::testing {

// A table with its circles and the cell side to call propagate_sectors with.
struct SectorTable {
  double R = 10;
  double a = 1;
  double cell = 2;
  Coordinates c;
  Velocities v;
  int n() const { return static_cast<int>(c.rows()); }
};

// R / (root of the sum of squared speeds): a time scale that collisions do not change.
inline double sector_time_scale(const SectorTable& t) { return t.R / std::sqrt(t.v.squaredNorm()); }

// The student's propagate_sectors, recorded for the pictures of a failing case.
inline Collision recorded_sectors_step(double R, double a, int n, Coordinates& c, Velocities& v, double cell) {
  return recorded_step(table_board(R, a, {}, Vector::Zero(), cell), c, v,
                       [&] { return propagate_sectors(R, a, n, c, v, cell); });
}

// Compares one step of the student's propagate_sectors from `t` with the oracle; returns false
// after reporting the first difference. `hint` is shown when the wrong event is chosen.
inline bool sectors_step_matches_oracle(const SectorTable& t, const std::string& where, const std::string& hint) {
  Coordinates c = t.c;
  Velocities v = t.v;
  Collision got{};
  try {
    got = recorded_sectors_step(t.R, t.a, t.n(), c, v, t.cell);
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(text(where, ": the next collision of a valid state"),
                             text("propagate_sectors threw std::invalid_argument: \"", error.what(), "\""),
                             "a valid state must never be refused: after a collision circles touch and may overlap "
                             "or stick out by rounding (~1e-15); use the checks:: functions, which allow for it.");
    return false;
  }
  const OracleComparison comparison = compare_with_oracle(t.R, t.a, t.c, t.v, sector_time_scale(t), got, c, v);
  using What = StepDifference::What;
  const What what = comparison.difference.what;
  if (comparison.match < 0 || what == What::Time) {
    const auto& events = comparison.expected.events;
    const auto& first = events.front();
    std::string also;
    for (std::size_t k = 1; k < events.size(); ++k) {
      also += text(" or ", describe_event(events[k].circle, events[k].other), " (a tie)");
    }
    ADD_FAILURE() << explain(text(where, ": the earliest event, ", describe_event(first.circle, first.other),
                                  " after time ", first.time, also, " (as all-pairs propagate finds it)"),
                             text("returned ", describe_collision(got)), hint);
    return false;
  }
  if (what == What::Position || what == What::Velocity) {
    const OracleEvent& match = comparison.event();
    ADD_FAILURE() << explain(text(where, ": after ", describe_event(match.circle, match.other),
                                  ", every circle moved by v t and the colliding one(s) given new velocities as in "
                                  "propagate"),
                             text("positions off by up to ", comparison.difference.position_error,
                                  ", velocities by up to ", comparison.difference.velocity_error),
                             "once the collision is known, finish exactly as propagate does: move EVERY circle by "
                             "v * t (the positions passed in are those at the start of the call; crossings only "
                             "change your cell lists, never the coordinates), then change the colliding velocities.");
    return false;
  }
  return true;
}

// `steps` steps compared with the oracle, each from the oracle's own state, so that one
// mistake never spoils the next steps and the two never run apart (the dynamics is chaotic).
inline bool sectors_run_matches_oracle(SectorTable t, int steps, const std::string& label, const std::string& hint) {
  for (int e = 0; e < steps; ++e) {
    if (!sectors_step_matches_oracle(t, text(label, ", step ", e), hint)) return false;
    const OracleStep next = oracle_step(t.R, t.a, t.c, t.v, 0);
    if (next.events.empty()) return true;
    oracle_advance(next, t.c, t.v);
  }
  return true;
}

}  // namespace billiard::testing
