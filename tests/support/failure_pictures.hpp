// Pictures of a failing case. When a graded test of a task where a state evolves (propagate,
// movie and the stages) fails, its message ends with the line "Picture: FILE": an SVG of the
// table at the step that went wrong, every circle numbered at its place with its velocity as an
// arrow, the expected event (its circles drawn where they touch, the point of contact marked) and
// what the student's code did, in two colours and two dash patterns, with a legend that repeats
// the message.
//
// How a suite takes part:
//   - it calls the student's step function through recorded_step(), which remembers each step
//     of the running test (the state before, what the student's code returned, the state after);
//   - it registers once a StepJudge, which computes the expected step from a state (an oracle or
//     the finished library) and says whether the student's step agrees with it;
//   - or, where no step function is called (the movie), it sets a CaseSource for the test.
// On the test's first failure, explain() (student_messages.hpp) asks for the picture: the first
// recorded step the judge disagrees with, so that a failure found after many steps shows where
// the run first left the expected one, not the end. Without disagreement, the last step.
//
// Pictures are written only when the environment variable BILLIARD_PICTURES names a folder
// (CTest sets it to Testing/pictures in the build folder; the grader sets it for the tests it
// may show), as FOLDER/<Suite>.<Test>.svg. A test's old picture is removed when it starts, so
// the folder holds the pictures of the last run's failures only.
#pragma once

#include "billiard/extensions.hpp"

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace billiard::testing {

// The table a step starts from.
struct Board {
  double table_radius = 0;
  double circle_radius = 0;
  std::vector<Wall> walls;          // task 8: straight walls; Collision::other = wall_id(k)
  Vector gravity = Vector::Zero();  // task 7: the circles fly on parabolas
  double cell_size = 0;             // task 9: the cells, drawn as a grid (0: none)
  Coordinates coordinates;
  Velocities velocities;
};

// A board's table, walls, gravity and cells (recorded_step adds the state).
inline Board table_board(double table_radius, double circle_radius, std::vector<Wall> walls = {},
                         const Vector& gravity = Vector::Zero(), double cell_size = 0) {
  Board board;
  board.table_radius = table_radius;
  board.circle_radius = circle_radius;
  board.walls = std::move(walls);
  board.gravity = gravity;
  board.cell_size = cell_size;
  return board;
}

// What a step did: the event and the state just after it, or the error it threw.
struct Outcome {
  Collision event{0, -1, kWall};
  Coordinates coordinates;
  Velocities velocities;
  std::string error;  // what the call threw; empty if it returned
  bool none = false;  // no event can happen (the expected outcome of a state at rest)
};

// A suite's verdict on one step: the expected outcome from the board, and whether the
// student's outcome agrees with it within the suite's tolerances (a tie counts as agreeing).
struct Judgement {
  Outcome expected;
  bool agrees = true;
};
using StepJudge = std::function<Judgement(const Board& board, const Outcome& got)>;

// Registers the suite's judge of the student's `function` (once per test program); returns true,
// for a static initialiser.
bool register_step_judge(std::string function, StepJudge judge);

// A recorded step of the running test that the suite's judge disagrees with: the board, what
// the student's code did, the judge's expected outcome, and which call of the test it was (from 1).
struct Departure {
  Board board;
  Outcome got;
  Outcome expected;
  int call = 0;
};
// The running test's first such step, if any: where a failure found after many steps began, for
// its picture and its hint.
std::optional<Departure> first_departure();

// Calls `call` (the student's step function, which moves `coordinates` and `velocities`, the
// state of `board`) and records the step for the running test. Returns what it returns;
// rethrows what it throws (recorded as the outcome).
template <typename Call>
Collision recorded_step(Board board, Coordinates& coordinates, Velocities& velocities, Call&& call);

// One account of what happens, drawn over the board: the expected one or the student's.
struct Ghost {
  int circle = -1;
  Vector at = Vector::Zero();        // where the account puts the circle
  Vector velocity = Vector::Zero();  // its velocity there
  bool moved = false;                // drawn with its velocity (false: only where it is)
};
struct Account {
  std::string label;            // "circles 0 and 1 collide after time 4"
  std::vector<Ghost> ghosts;    // the event's circles where they touch, and others it puts elsewhere
  std::vector<Vector> contacts;  // points of contact
  int wall = -1;                // the straight wall it touches (walls[wall]), or -1
  std::vector<std::pair<int, std::string>> not_finite;  // (circle, "velocity is NaN", ...): marked where it was
};
// Lines of a file the student's code wrote, for a failure about its text (lines_case).
struct Listing {
  std::string file_name;
  std::vector<std::pair<int, std::string>> lines;  // (line number, text), in order; number 0: a gap
  std::vector<int> marked;                          // the lines the message is about
};
struct FailingCase {
  // "step": a call of a step function; "positions": the discs at one moment against where
  // something else puts them (the movie); "state": a state and nothing else (mean_energy);
  // "lines": a file's lines (the movie's SVG when its text is what is wrong), no table.
  std::string kind = "step";
  std::string heading;  // "propagate call 3 of 40 in this test: the first where ..."
  Board board;          // the state drawn, circles at their places with their velocities
  Account expected, yours;
  Outcome expected_outcome, your_outcome;  // as the metadata records them
  std::string key;  // what the drawing shows, for the legend ("" for a step's)
  Listing listing;  // for "lines"
};

// For a test without steps: a function that draws its case when it fails (nullopt: nothing to
// draw). Replaces any earlier one of the running test.
using CaseSource = std::function<std::optional<FailingCase>()>;
void set_case_source(CaseSource source);

// Builds the case of one step: the board, the expected outcome and the student's.
FailingCase step_case(const Board& board, const Outcome& expected, const Outcome& yours, std::string heading);

// The case of a test on a state that does not evolve (such as mean_energy's): the circles with
// their velocities (and gravity), no event. With table_radius 0, a table that holds them all.
FailingCase state_case(Board board, std::string heading);

// The case of a failure about a file's text: its lines around the `marked` ones (numbered from
// 1; none: the file's first lines), the marked ones highlighted.
FailingCase lines_case(std::string_view file_text, std::string file_name, std::vector<int> marked, std::string heading);

// "circles 0 and 1 collide after time 4", "circle 2 hits walls[1] after time 3", ...
std::string describe_outcome(const Outcome& outcome, int circles, int walls);

// Writes the picture of `failing` with the message's lines under it; throws std::runtime_error.
void draw_failing_case(const FailingCase& failing, std::string_view test, std::string_view expected,
                       std::string_view got, const std::string& file);

// The picture of the running test's failure, written the first time this is called in a test
// (later calls return the same file): its path, or "" when there is nothing to draw or pictures
// are off. Called by explain().
std::string picture_of_failure(std::string_view expected, std::string_view got);

// Installs the listener that resets the record and removes a test's old picture when it starts
// (graded_main.cpp calls this once).
void install_picture_listener();

// --- implementation of the template above ------------------------------------------------------

void record_step(Board&& board, Outcome&& outcome);

template <typename Call>
Collision recorded_step(Board board, Coordinates& coordinates, Velocities& velocities, Call&& call) {
  board.coordinates = coordinates;
  board.velocities = velocities;
  Outcome outcome;
  try {
    outcome.event = call();
  } catch (const std::exception& error) {
    outcome.error = error.what();
    outcome.coordinates = coordinates;
    outcome.velocities = velocities;
    record_step(std::move(board), std::move(outcome));
    throw;
  }
  outcome.coordinates = coordinates;
  outcome.velocities = velocities;
  const Collision event = outcome.event;
  record_step(std::move(board), std::move(outcome));
  return event;
}

}  // namespace billiard::testing
