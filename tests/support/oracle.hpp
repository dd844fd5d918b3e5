// An independent implementation of one `propagate` step, used by the graded suite of task 4 to
// check the student's propagate one step at a time from many random states.
//
// It is deliberately computed differently from a straightforward solution: all arithmetic in
// long double, the cancellation-free quadratic forms of lib/PHYSICS.md, touching and
// overlapping pairs (rounding) handled explicitly, and a circle on or outside the wall that
// moves outward reflected at once. It reports every event within a small tie window of the
// earliest one, each with the state it leads to, so that a student's code may process
// near-simultaneous events in either order.
//
// Never compare whole trajectories with it: the dynamics is chaotic and amplifies rounding;
// compare single steps from the same starting state.
#pragma once

#include "billiard/course.hpp"
#include "support/failure_pictures.hpp"
#include "support/step_difference.hpp"

#include <string>
#include <vector>

namespace billiard::testing {

// One possible next event and the state it leads to if processed first.
struct OracleEvent {
  double time = 0;  // time from the starting state to the event (>= 0)
  int circle = -1;  // for a circle-circle event the smaller index
  int other = -1;   // the larger index, or kWall
  Coordinates coordinates;  // every circle moved by `time`,
  Velocities velocities;    // and the colliding circle(s) given their new velocities
};

struct OracleStep {
  double time = 0;                  // earliest event time; +infinity if no event can ever happen
  std::vector<OracleEvent> events;  // every event within tie_window of `time`, earliest first
                                    // (empty when time is infinite)
};

// One event step of n = coordinates.rows() circles of radius a on a table of radius R.
// tie_window is an absolute time: events up to time + tie_window are all reported.
OracleStep oracle_step(double R, double a, const Coordinates& coordinates, const Velocities& velocities,
                       double tie_window);

// The state after the earliest event (events.front()); the oracle's own trajectory.
void oracle_advance(const OracleStep& step, Coordinates& coordinates, Velocities& velocities);

// Whether `collision` names the same event (a pair in either order; the wall as kWall).
bool same_event(const OracleEvent& event, const Collision& collision);

// "circle 3 with the wall" or "circles 2 and 7".
std::string describe_event(int circle, int other);

// A student's step (its event `got` and the state it left, c and v) against the oracle's from
// the state before it (c0, v0): the tied event it names (match; -1 if none) and how it differs
// from that event's step. `scale` is the suite's time scale: events within 1e-9 of it are ties.
struct OracleComparison {
  OracleStep expected;
  int match = -1;
  StepDifference difference;
  bool agrees() const { return match >= 0 && difference.none(); }
  const OracleEvent& event() const { return expected.events[static_cast<std::size_t>(match >= 0 ? match : 0)]; }
};
OracleComparison compare_with_oracle(double R, double a, const Coordinates& c0, const Velocities& v0, double scale,
                                     const Collision& got, const Coordinates& c, const Velocities& v);

// The judge of a step on a plain table (propagate, propagate_sectors) for the pictures of a
// failing case: the oracle's step from the board, with the suites' tolerances (1e-9 of the time
// scale R / sqrt(sum |v|^2), of R for positions, of that root speed for velocities; events within
// 1e-9 of the time scale of the earliest are ties, any of them right).
Judgement oracle_judgement(const Board& board, const Outcome& got);

// Largest speed |v_i| (0 if there are no circles or all are at rest).
double max_speed(const Velocities& velocities);

}  // namespace billiard::testing
