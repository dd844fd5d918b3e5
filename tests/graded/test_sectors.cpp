// Graded tests of task 9, `propagate_sectors`: propagate's event step, with the next collision
// found through square cells instead of all pairs.
//
// What is checked, and why:
//   1. Hand-computed cases (sections 1-3), each aimed at one part of the method: pairs in
//      neighbouring cells, pairs that only become neighbours after one or several cell
//      crossings (by either circle, by both, through a cell corner), circles exactly on cell
//      faces, and a collision that is not yet certain while an earlier crossing is pending.
//      Numbers are of order 1 to 10, so double precision gives ~1e-15; the tests allow 1e-12.
//   2. The same result as all-pairs propagate (section 4): every step of hundreds of random
//      states, for several densities and cell sizes (from exactly 2a to one cell for the whole
//      table), is compared with the independent oracle (support/oracle.hpp, long double) from
//      a SHARED state: the dynamics is chaotic (rounding grows ~1e10-fold in 1000 events), so
//      two long trajectories are never compared. Tolerance 1e-9 of the time, length and speed
//      scales: far above rounding, far below any real mistake; events within 1e-9 of the
//      earliest are ties and either is right. Large tables are also compared with the finished
//      library (billiard::Simulation, an event queue with its own cells), first event only.
//   3. Conservation over a long run (section 5): <v^2> to 1e-10 relative and angular momentum
//      to 1e-9 of sum |r||v| (rounding random-walks by ~1e-16 per collision); no overlap and no
//      escape beyond 1e-9; no immediate repeat of a collision.
//   4. Efficiency (section 6): the provided pair_time counts its calls, so the suite counts the
//      pair tests of one call on dilute tables of 1000 circles, which must be 20 and 100 times
//      fewer than the n (n - 1) / 2 of all pairs, and grow about linearly with n: that count
//      gives the hint. It is the student's code's word about its own work, so it earns nothing
//      alone: each of the two tests then steps a dilute table of 200,000 circles, whose first
//      collision must be the library's, within the test's time limit, which the grader sets
//      from the reference solution's CPU time and enforces from outside the student's process.
//      Testing all pairs there (2 x 10^10 pair tests a step) takes far longer than the cells.
//      Code that tests all pairs keeps every correctness point and loses these; code that never
//      calls pair_time cannot be measured and loses them too.
//   5. Argument errors (section 7) name the argument and leave the state unchanged.
#include "graded/sectors_support.hpp"
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/oracle.hpp"
#include "support/student_messages.hpp"

#include "billiard/engine/simulation.hpp"
#include "billiard/extensions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

// A failing test draws the step that went wrong (support/failure_pictures.hpp).
const bool kPicturesJudged = billiard::testing::register_step_judge("propagate_sectors", billiard::testing::oracle_judgement);

using billiard::Collision;
using billiard::Coordinates;
using billiard::kWall;
using billiard::Velocities;
using billiard::testing::describe_collision;
using billiard::testing::explain;
using billiard::testing::row;
using billiard::testing::SectorTable;
using billiard::testing::text;

constexpr double kTol = 1e-12;  // hand-made cases: numbers of order 10, rounding ~1e-15

bool is_pair(const Collision& c, int i, int j) {
  return (c.circle == i && c.other == j) || (c.circle == j && c.other == i);
}
bool is_wall(const Collision& c, int i) { return c.circle == i && c.other == kWall; }

SectorTable table(double R, double a, double cell, std::initializer_list<double> rows) {
  SectorTable t{R, a, cell, Coordinates(static_cast<Eigen::Index>(rows.size() / 4), 2),
                Velocities(static_cast<Eigen::Index>(rows.size() / 4), 2)};
  auto value = rows.begin();
  for (int i = 0; i < t.n(); ++i) {
    t.c(i, 0) = *value++;
    t.c(i, 1) = *value++;
    t.v(i, 0) = *value++;
    t.v(i, 1) = *value++;
  }
  return t;
}

// One call of the student's propagate_sectors on a hand-made table that expects the event
// (circle, other) after `time`. Reports a wrong event, a wrong time or a refused valid state
// with `situation` and `hint`; returns whether the call gave the expected event.
bool expect_event(SectorTable& t, int circle, int other, double time, const std::string& situation,
                  const std::string& hint) {
  const std::string expected =
      text(situation, ": ", billiard::testing::describe_event(circle, other), " after time ", time);
  Collision got{};
  try {
    got = billiard::testing::recorded_sectors_step(t.R, t.a, t.n(), t.c, t.v, t.cell);
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(expected, text("it threw std::invalid_argument: \"", error.what(), "\""), hint);
    return false;
  }
  const bool event_ok = other == kWall ? is_wall(got, circle) : is_pair(got, circle, other);
  if (!event_ok || !(std::abs(got.time - time) <= kTol)) {
    ADD_FAILURE() << explain(expected, text("returned ", describe_collision(got)), hint);
    return false;
  }
  return true;
}

void expect_row(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int i, double x, double y,
                const std::string& what, const std::string& hint) {
  const double error = std::hypot(rows(i, 0) - x, rows(i, 1) - y);
  EXPECT_LE(error, kTol) << explain(text(what, " to be (", x, ", ", y, ")"), text("it is ", row(rows, i)), hint);
}

const char* const kHintWall =
    "compute every circle's wall time exactly as in propagate (positive root of |r + v t| = R - a) and include it "
    "in the earliest event; the cells are only for the pairs, every circle can reach the wall.";
const char* const kHintPairTime =
    "for every pair you test, call the provided pair_time(circle_radius, coordinates, velocities, i, j) (+infinity "
    "when the pair never meets) and keep the smallest time; then move every circle by v t and collide as in "
    "propagate.";
const char* const kHintNeighbours =
    "test each circle against the circles in its own cell AND in the 8 neighbouring cells (the 3x3 block around "
    "it): circles in neighbouring cells can be as close as touching.";
const char* const kHintCrossing =
    "circles in cells that are not neighbours only meet after cell crossings: while the earliest pending crossing "
    "comes before the earliest collision found so far, take it (the circle leaves its cell when its centre reaches "
    "the face it moves towards: x = -R + (ix + 1) s for vx > 0, x = -R + ix s for vx < 0), move the circle into "
    "the next cell, and test it against the row of three cells that has just become neighbouring (the row beyond "
    "its new cell, not the one behind it).";
const char* const kHintCrossingIndex =
    "after a crossing, test the crossing circle against EVERY circle in the newly neighbouring cells, whatever its "
    "index: the rule j > i (each pair once) is only for the first pass over the cells.";
const char* const kHintCellLists =
    "when a circle crosses into another cell, move it in your cell lists too (remove it from the old cell, add it "
    "to the new one), so that a circle crossing later finds it in the cell where it is now.";
const char* const kHintCorner =
    "at a cell corner a circle crosses two faces at the same time: take both crossings, one after the other at "
    "the same time (x, then y), or the circle stays in the wrong cell and misses its new neighbours.";
const char* const kHintFaces =
    "a circle exactly on a face belongs to the cell above it (std::floor((x + R) / s)); moving back through that "
    "face it crosses at t = 0, once: keep the cell indices yourself (ix -= 1) instead of recomputing them with "
    "floor from the position. A circle moving along a face (vx = 0) never crosses it: no division by zero.";
const char* const kHintNotCertain =
    "a collision found so far is certain only when no pending crossing comes before it: keep taking crossings in "
    "time order (a priority queue) while the earliest crossing is earlier than the earliest collision found, even "
    "after a crossing has found a pair; a crossing that comes first may find a pair that collides sooner.";
const char* const kHintSameAsPropagate =
    "propagate_sectors must return exactly what all-pairs propagate returns: every wall time, the pairs in the "
    "3x3 block of cells, and the pairs found after each cell crossing that comes before the earliest collision.";

// ---------------------------------------------------------------------------------------------
// 1. Sanity: one circle, one cell, neighbouring cells, a crossing.

GRADED_TEST(Sectors, SingleCircleHitsWallThroughSeveralCells, 2, visible) {
  // R = 10, a = 1, cells of side 2: from the centre at speed 1 the circle crosses the faces
  // x = 2, 4, 6, 8 and reaches the wall at x = 9 after time 9.
  SectorTable t = table(10, 1, 2, {0, 0, 1, 0});
  if (!expect_event(t, 0, kWall, 9, "a circle from the centre moving (1, 0), R = 10, a = 1, cell_size = 2", kHintWall)) {
    return;
  }
  expect_row(t.c, 0, 9, 0, "the circle's position at the wall", kHintPairTime);
  expect_row(t.v, 0, -1, 0, "the velocity after a head-on wall hit", "reflect as in propagate: v' = v - 2 (v.n) n.");
}

GRADED_TEST(Sectors, HeadOnPairWhenOneCellCoversTheTable, 2, visible) {
  // cell_size = 2R: one cell holds everything, so this is propagate. Contact at time 4.
  SectorTable t = table(10, 1, 20, {-5, 0, 1, 0, 5, 0, -1, 0});
  if (!expect_event(t, 0, 1, 4, "circles at (-5, 0) and (5, 0) closing at speed 2, cell_size = 2R", kHintPairTime)) {
    return;
  }
  expect_row(t.c, 0, -1, 0, "circle 0's position at the collision", kHintPairTime);
  expect_row(t.v, 0, -1, 0, "circle 0's velocity after the head-on collision", kHintPairTime);
  expect_row(t.v, 1, 1, 0, "circle 1's velocity after the head-on collision", kHintPairTime);
}

GRADED_TEST(Sectors, PairInNeighbouringCellsCollides, 2, visible) {
  // R = 10, a = 0.5, cells of side 2 with faces at the even numbers. Circles at x = -1 and
  // x = 1 sit in neighbouring cells and touch (centres 1 apart) after time 0.5, before either
  // leaves its cell (time 1). The same along a diagonal: cells (-2..0)^2 and (0..2)^2.
  {
    SectorTable t = table(10, 0.5, 2, {-1, 0.5, 1, 0, 1, 0.5, -1, 0});
    if (!expect_event(t, 0, 1, 0.5, "circles at (-1, 0.5) and (1, 0.5) in side-by-side cells", kHintNeighbours)) return;
  }
  const double s = 1 / std::sqrt(2.0);
  SectorTable t = table(10, 0.5, 2, {-1, -1, s, s, 1, 1, -s, -s});
  expect_event(t, 0, 1, (2 * std::sqrt(2.0) - 1) / 2, "circles at (-1, -1) and (1, 1) in diagonal cells",
               kHintNeighbours);
}

GRADED_TEST(Sectors, PairMeetsAfterCrossings, 3, visible) {
  // R = 10, a = 0.5, cell_size = 2a = 1: faces at the integers. Circle 0 from x = -3.25
  // crosses x = -3, -2, -1 (times 0.25, 1.25, 2.25) before circle 1, at rest at x = 0.25
  // three cells away, is in a neighbouring cell; they touch when 1 apart, after time 2.5.
  // Circle 2 reaches the wall at time 3: a pair found only by later crossings comes too late.
  SectorTable t = table(10, 0.5, 1, {-3.25, 0.2, 1, 0, 0.25, 0.2, 0, 0, 0, -6.5, 0, -1});
  if (!expect_event(t, 0, 1, 2.5, "circle 0 from (-3.25, 0.2) moving (1, 0) towards circle 1 at rest at (0.25, 0.2)",
                    kHintCrossing)) {
    return;
  }
  expect_row(t.c, 0, -0.75, 0.2, "circle 0 at the collision", kHintPairTime);
  expect_row(t.v, 1, 1, 0, "circle 1's velocity after being hit head-on", kHintPairTime);
}

GRADED_TEST(Sectors, CrossingTimesComeFromTheFaceAhead, 2, visible) {
  // Faces at the integers. Circle 1 drifts slowly right in cell [0, 1) x [0, 1) and leaves it
  // only at time 10; circle 0 moves up from (-0.2, -2.5), crossing y = -2, -1, 0 at times
  // 0.5, 1.5, 2.5. They touch when (0.7 + 0.05 t)^2 + (2.8 - t)^2 = 1, i.e.
  // 1.0025 t^2 - 5.53 t + 7.33 = 0, at the smaller root (about 2.215).
  SectorTable t = table(10, 0.5, 1, {-0.2, -2.5, 0, 1, 0.5, 0.3, 0.05, 0});
  const double A = 1.0025, B = -5.53, C = 7.33;
  expect_event(t, 0, 1, (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A),
               "circle 0 from (-0.2, -2.5) moving (0, 1) and circle 1 from (0.5, 0.3) moving (0.05, 0)", kHintCrossing);
}

// ---------------------------------------------------------------------------------------------
// 2. Crossings: by the circle with the larger index, by both circles, through a corner.

GRADED_TEST(Sectors, CrossingCircleFindsACircleWithASmallerIndex, 2, visible) {
  // As PairMeetsAfterCrossings, with the rows swapped: now circle 1 crosses and meets circle 0.
  SectorTable t = table(10, 0.5, 1, {0.25, 0.2, 0, 0, -3.25, 0.2, 1, 0});
  expect_event(t, 0, 1, 2.5, "circle 1 from (-3.25, 0.2) moving (1, 0) towards circle 0 at rest at (0.25, 0.2)",
               kHintCrossingIndex);
}

GRADED_TEST(Sectors, BothCirclesCrossBeforeTheyMeet, 2, visible) {
  // Circles 10 cells apart close at speed 2; each crosses 4 faces before they touch at time
  // 4.5 (centres at -0.5 and 0.5). They become neighbours only after both have moved.
  // Circle 2 reaches the wall at time 5, before the circles would find each other where they
  // started.
  SectorTable t = table(10, 0.5, 1, {-5, 0.3, 1, 0, 5, 0.3, -1, 0, 0, -4.5, 0, -1});
  expect_event(t, 0, 1, 4.5, "circles at (-5, 0.3) and (5, 0.3) closing at speed 2, cell_size = 1", kHintCellLists);
  // Two circles crossing cells at right angles: circle 0 along y = 0.2, circle 1 along
  // x = 0.2; they touch when sqrt(2) |t - 3.45| = 1, after time 3.45 - 1/sqrt(2).
  SectorTable p = table(10, 0.5, 1, {-3.25, 0.2, 1, 0, 0.2, -3.25, 0, 1});
  expect_event(p, 0, 1, 3.45 - 1 / std::sqrt(2.0), "circle 0 moving (1, 0) from (-3.25, 0.2) and circle 1 moving "
               "(0, 1) from (0.2, -3.25)", kHintCellLists);
  // Three movers: circles 0 and 2 overtake circle 1 from both sides.
  SectorTable u = table(10, 0.5, 1, {-6.5, -2.5, 2, 0, -1.5, -2.5, 0.5, 0, 6.5, -2.5, -1, 0});
  // Circle 0 catches up with circle 1 (gap 5 - 1 = 4 at relative speed 1.5) at 8/3; circle 2
  // meets circle 1 (gap 8 - 1 = 7 at closing speed 1.5) at 14/3.
  expect_event(u, 0, 1, 8.0 / 3, "circle 0 catching up with circle 1, both crossing cells", kHintCellLists);
}

GRADED_TEST(Sectors, CrossingThroughACellCorner, 3, visible) {
  // Faces at the integers. Circle 0 moves along the diagonal from (-0.5, -0.5) and passes the
  // corner (0, 0) at time 0.5, crossing x = 0 and y = 0 at once, then the corner (1, 1) at
  // time 1.5; only then is circle 1, at rest at (2.2, 2.2), in a neighbouring cell. They touch
  // when sqrt(2) (2.7 - t) = 1, after time 2.7 - 1/sqrt(2).
  SectorTable t = table(10, 0.5, 1, {-0.5, -0.5, 1, 1, 2.2, 2.2, 0, 0});
  if (!expect_event(t, 0, 1, 2.7 - 1 / std::sqrt(2.0), "circle 0 moving (1, 1) through the corners (0, 0) and (1, 1)",
                    kHintCorner)) {
    return;
  }
  // The other diagonal, and a corner that is not at the origin: from (3.5, -1.5) moving
  // (-1, 1) through (3, -1) and (2, 0) towards circle 1 at rest at (0.8, 1.2).
  SectorTable u = table(10, 0.5, 1, {3.5, -1.5, -1, 1, 0.8, 1.2, 0, 0});
  expect_event(u, 0, 1, 2.7 - 1 / std::sqrt(2.0), "circle 0 moving (-1, 1) through the corners (3, -1) and (2, 0)",
               kHintCorner);
}

GRADED_TEST(Sectors, CirclesOnCellFaces, 2, after_due_date) {
  // Faces at the integers (R = 10, cell_size = 1).
  // (a) Circle 0 on the corner (0, 0) moving (-1, 0) leaves its cell at t = 0 and meets
  //     circle 1, at rest at (-3, 0), when 1 apart: time 2.
  SectorTable a = table(10, 0.5, 1, {0, 0, -1, 0, -3, 0, 0, 0});
  if (!expect_event(a, 0, 1, 2, "circle 0 on the corner (0, 0) moving (-1, 0) towards circle 1 at (-3, 0)",
                    kHintFaces)) {
    return;
  }
  // (b) Circle 0 moves along the face x = 0 from (0, -4); circle 1 rests at (0.8, 3). They
  //     touch when (7 - t)^2 + 0.64 = 1: time 6.4.
  SectorTable b = table(10, 0.5, 1, {0, -4, 0, 1, 0.8, 3, 0, 0});
  if (!expect_event(b, 0, 1, 6.4, "circle 0 moving along the face x = 0 towards circle 1 at (0.8, 3)", kHintFaces)) {
    return;
  }
  // (c) Circle 1 rests on the corner (1, 1); circle 0 from (-2, 1) moving (1, 0) crosses
  //     x = -1 at time 1 and x = 0 at time 2, the moment it touches circle 1.
  SectorTable c = table(10, 0.5, 1, {-2, 1, 1, 0, 1, 1, 0, 0});
  expect_event(c, 0, 1, 2, "circle 0 from (-2, 1) moving (1, 0) towards circle 1 resting on the corner (1, 1)",
               kHintFaces);
}

GRADED_TEST(Sectors, LaterCollisionIsNotCertainWhileACrossingIsPending, 3, visible) {
  // R = 50, faces at the integers. Circle 0, slow, crosses x = 0 at time 0.5 and finds circle
  // 1 (at rest at (1.5, 10.5)): contact after time 5.5. But circle 2 crosses x = -20 at time
  // 0.8 and then finds circle 3 (at rest at (-17.5, -10)): contact after time 2.3, earlier.
  SectorTable t = table(50, 0.5, 1, {-0.05, 10.5, 0.1, 0, 1.5, 10.5, 0, 0, -20.8, -10, 1, 0, -17.5, -10, 0, 0});
  expect_event(t, 2, 3, 2.3, "circles 2 and 3 (found after a crossing at time 0.8) before circles 0 and 1 (at 5.5)",
               kHintNotCertain);
}

// ---------------------------------------------------------------------------------------------
// 3. Step by step against the oracle (all pairs, long double), from a shared state.

// A random table: n circles at area fraction `fraction` on a table of radius R, Gaussian
// velocities times a speed scale, in every fourth table half the circles at rest, and the
// cell side `cell_factor` times 2a (capped at 2R: one cell).
SectorTable random_table(std::uint64_t seed, int n, double R, double fraction, double cell_factor) {
  std::mt19937_64 rng(seed);
  const double a = std::min(R * std::sqrt(fraction / n), 0.45 * R);
  SectorTable t{R, a, std::min(2 * a * cell_factor, 2 * R), billiard::testing::scattered_circles(R, a, n, seed),
                billiard::testing::gaussian_velocities(n, seed + 1)};
  const double speeds[] = {0.01, 1.0, 30.0};
  t.v *= speeds[seed % 3];
  if (seed % 4 == 0 && n > 1) {
    for (int i = 0; i < n; i += 2) t.v.row(i).setZero();
  }
  return t;
}

std::string label(const SectorTable& t, const char* kind, int k) {
  return text(kind, " table ", k, " (n = ", t.n(), ", R = ", t.R, ", a = ", t.a, ", cell_size = ", t.cell, ")");
}

GRADED_TEST(Sectors, OneCellForTheWholeTableMatchesPropagate, 2, after_due_date) {
  // cell_size >= 2R: a single cell, no crossings; this is propagate with pair_time.
  for (int k = 0; k < 12; ++k) {
    SectorTable t = random_table(300 + static_cast<std::uint64_t>(k), 2 + 3 * k, k % 2 ? 10 : 3.7, 0.15, 1);
    t.cell = (k % 3 == 0 ? 2 : 5) * t.R;
    if (!billiard::testing::sectors_run_matches_oracle(t, 40, label(t, "one-cell", k), kHintPairTime)) return;
  }
}

GRADED_TEST(Sectors, MatchesPropagateStepByStepOnDiluteTables, 3, after_due_date) {
  // 24 tables, 5 to 120 circles at 2% to 15%, radii 1 to 250, cells of 2a to 6a; 60 steps each.
  const double radii[] = {1, 10, 37, 250};
  const double factors[] = {1, 1.3, 2, 3};
  for (int k = 0; k < 24; ++k) {
    const double fraction = 0.02 + 0.13 * (k % 5) / 4;
    SectorTable t = random_table(1000 + static_cast<std::uint64_t>(k), 5 + 5 * k, radii[k % 4], fraction, factors[(k / 4) % 4]);
    if (!billiard::testing::sectors_run_matches_oracle(t, 60, label(t, "dilute", k), kHintSameAsPropagate)) return;
  }
}

GRADED_TEST(Sectors, MatchesPropagateWithCellsOfExactlyOneDiameter, 3, after_due_date) {
  // cell_size = 2a exactly, the smallest allowed: touching circles (centres 2a apart) are at
  // most one cell apart along each axis, so the 3x3 block just suffices; 80 steps each.
  for (int k = 0; k < 16; ++k) {
    SectorTable t = random_table(2000 + static_cast<std::uint64_t>(k), 20 + 4 * k, k % 2 ? 10 : 25, 0.05 + 0.02 * (k % 8), 1);
    if (!billiard::testing::sectors_run_matches_oracle(t, 80, label(t, "cell = 2a", k), kHintSameAsPropagate)) return;
  }
}

GRADED_TEST(Sectors, MatchesPropagateOnCrowdedTables, 3, after_due_date) {
  // 25% to 32% of the table covered: many circles per cell, mostly circle-circle collisions.
  for (int k = 0; k < 12; ++k) {
    SectorTable t = random_table(3000 + static_cast<std::uint64_t>(k), 30 + 5 * k, 10, 0.25 + 0.07 * (k % 4) / 3,
                                 k % 3 == 0 ? 1 : 2.5);
    if (!billiard::testing::sectors_run_matches_oracle(t, 80, label(t, "crowded", k), kHintSameAsPropagate)) return;
  }
}

GRADED_TEST(Sectors, MatchesPropagateOnALatticeOfCellFaces, 2, after_due_date) {
  // Circles on the corners of the cells (faces at multiples of 1 from -R), moving along the
  // axes and the diagonals: crossings at t = 0, at corners, along faces, and many ties. The
  // radius 0.45 keeps 2a away from the lattice's distances (1, 1/sqrt(2), ...): paths exactly
  // 2a apart would graze, where rounding decides whether two circles touch.
  for (int k = 0; k < 6; ++k) {
    std::mt19937_64 rng(4000 + static_cast<std::uint64_t>(k));
    std::uniform_int_distribution<int> site(-6, 6), direction(-1, 1);
    SectorTable t{10, 0.45, k % 2 ? 1.0 : 2.0, Coordinates(0, 2), Velocities(0, 2)};
    std::vector<std::pair<int, int>> sites;
    for (int tries = 0; tries < 400 && sites.size() < 30; ++tries) {
      const std::pair<int, int> s{site(rng), site(rng)};
      bool free = true;
      for (const auto& o : sites) free = free && std::max(std::abs(o.first - s.first), std::abs(o.second - s.second)) >= 2;
      if (free) sites.push_back(s);
    }
    t.c.resize(static_cast<Eigen::Index>(sites.size()), 2);
    t.v.resize(static_cast<Eigen::Index>(sites.size()), 2);
    for (int i = 0; i < t.n(); ++i) {
      t.c.row(i) << sites[static_cast<std::size_t>(i)].first, sites[static_cast<std::size_t>(i)].second;
      t.v.row(i) << direction(rng), direction(rng);
    }
    if (!billiard::testing::sectors_run_matches_oracle(t, 60, label(t, "lattice", k), kHintFaces)) return;
  }
}

// The first collision of one call from the table's state, compared with the finished library's
// own event queue and cells (billiard::Simulation); `what` describes the table. A table too large
// to draw is stepped without recording the picture.
bool first_collision_is_the_librarys(const SectorTable& table, const std::string& what, bool drawn = true) {
  billiard::Simulation sim(billiard::circular_table(table.R));
  sim.add_discs(table.c, table.v, table.a);
  sim.set_log_events(true);
  sim.advance(1);
  const billiard::EventRecord& e = sim.event_log().front();
  const int other = e.other >= 0 && e.wall == billiard::kNoWall ? e.other : kWall;
  const std::string expected = text(what, ": the first collision, ", billiard::testing::describe_event(e.disc, other),
                                    " after time ", e.time, ", as the library finds it");
  SectorTable mine = table;
  Collision got{};
  try {
    got = drawn ? billiard::testing::recorded_sectors_step(mine.R, mine.a, mine.n(), mine.c, mine.v, mine.cell)
                : billiard::propagate_sectors(mine.R, mine.a, mine.n(), mine.c, mine.v, mine.cell);
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(expected, text("it threw std::invalid_argument: \"", error.what(), "\""), kHintSameAsPropagate);
    return false;
  }
  const bool event_ok = other == kWall ? is_wall(got, e.disc) : is_pair(got, e.disc, other);
  if (!event_ok || !(std::abs(got.time - e.time) <= 1e-9 * (1 + e.time))) {
    ADD_FAILURE() << explain(expected, text("returned ", describe_collision(got)), kHintSameAsPropagate);
    return false;
  }
  return true;
}

GRADED_TEST(Sectors, AgreesWithTheLibraryOnLargeTables, 2, after_due_date) {
  // 400 to 1200 circles, from fresh states.
  for (int k = 0; k < 4; ++k) {
    const int n = 400 + 250 * k;
    const double R = 60, a = 0.5;
    const double cell = k % 2 ? 2 * a : 6 * a;
    const SectorTable t{R, a, cell, billiard::testing::scattered_circles(R, a, n, 5000 + static_cast<std::uint64_t>(k)),
                        billiard::testing::gaussian_velocities(n, 5100 + static_cast<std::uint64_t>(k))};
    if (!first_collision_is_the_librarys(t, text("table of ", n, " circles (R = ", R, ", a = ", a, ", cell_size = ",
                                                 cell, ")"))) {
      return;
    }
  }
}

GRADED_TEST(Sectors, NoStateSurvivesBetweenCalls, 2, after_due_date) {
  // Calls alternate between two tables of different sizes and cell sizes, and the same state
  // is stepped with three cell sizes: each call must stand on its own.
  SectorTable big = random_table(6000, 80, 40, 0.05, 1);
  SectorTable small = random_table(6001, 12, 3, 0.2, 1.5);
  for (int e = 0; e < 40; ++e) {
    for (SectorTable* t : {&big, &small}) {
      if (!billiard::testing::sectors_step_matches_oracle(*t, text(t == &big ? "large" : "small",
                                                                   " table, alternating calls, step ", e),
                                                          "build the cells afresh in each call from the arguments "
                                                          "(no static or global variables): two tables, or two cell "
                                                          "sizes, may follow each other in any order.")) {
        return;
      }
      const auto next = billiard::testing::oracle_step(t->R, t->a, t->c, t->v, 0);
      billiard::testing::oracle_advance(next, t->c, t->v);
    }
    for (const double factor : {1.0, 2.5, 1e3}) {
      SectorTable same = big;
      same.cell = std::min(2 * big.a * factor, 2 * big.R);
      if (!billiard::testing::sectors_step_matches_oracle(same, text("large table, step ", e, ", cell_size ", same.cell),
                                                          "the cell size changes how the collision is found, never "
                                                          "which collision it is.")) {
        return;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 4. A long run with the student's own steps: conservation, no overlap, no escape.

constexpr int kLongRunCircles = 150;
#ifdef NDEBUG
constexpr int kLongRunCollisions = 3000;
#else
constexpr int kLongRunCollisions = 300;
#endif

SectorTable long_run_table() {
  SectorTable t{20, 0.5, 1, billiard::testing::scattered_circles(20, 0.5, kLongRunCircles, 7070),
                billiard::testing::gaussian_velocities(kLongRunCircles, 7070)};
  return t;
}

long double mean_square(const Velocities& v) {
  long double sum = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) sum += static_cast<long double>(v.row(i).squaredNorm());
  return sum / static_cast<long double>(v.rows());
}

// One step of the student's own trajectory; a refused valid state is reported.
bool own_step(SectorTable& t, Collision& got, int e) {
  try {
    got = billiard::testing::recorded_sectors_step(t.R, t.a, t.n(), t.c, t.v, t.cell);
    return true;
  } catch (const std::invalid_argument& error) {
    ADD_FAILURE() << explain(text("long run, collision ", e, ": the next collision of a valid state"),
                             text("it threw std::invalid_argument: \"", error.what(), "\""),
                             "after a collision circles touch and may overlap by rounding: use the checks:: "
                             "functions (they allow for it), and find the earliest event as propagate does.");
    return false;
  }
}

GRADED_TEST(Sectors, LongRunConservesEnergyAndAngularMomentum, 3, after_due_date) {
  SectorTable t = long_run_table();
  const long double start = mean_square(t.v);
  const double momentum = billiard::testing::angular_momentum(t.c, t.v);
  double scale = 0;  // sum_i |r_i| |v_i|: the size of the terms that make up the total
  for (int i = 0; i < t.n(); ++i) scale += t.c.row(i).norm() * t.v.row(i).norm();
  for (int e = 1; e <= kLongRunCollisions; ++e) {
    Collision got{};
    if (!own_step(t, got, e)) return;
    // Rounding: ~1e-16 per collision, a random walk; 1e-10 and 1e-9 leave wide margins.
    const double drift = static_cast<double>(std::abs(mean_square(t.v) - start) / start);
    const double change = std::abs(billiard::testing::angular_momentum(t.c, t.v) - momentum) / scale;
    if (!(drift <= 1e-10) || !(change <= 1e-9)) {
      ADD_FAILURE() << explain(
          text("<v^2> (to 1e-10 relative) and the angular momentum (to 1e-9 of sum |r||v|) to stay constant over ",
               kLongRunCollisions, " collisions of ", kLongRunCircles, " circles"),
          text("after collision ", e, " (", describe_collision(got), ") <v^2> drifted by ", drift,
               " and the angular momentum by ", change),
          "collide exactly as in propagate: at the wall reverse only the component along n = r / |r|, between "
          "circles exchange only the components along the line of centres, both at the moment of contact.");
      return;
    }
  }
}

GRADED_TEST(Sectors, LongRunKeepsCirclesApartAndOnTheTable, 3, after_due_date) {
  SectorTable t = long_run_table();
  for (int e = 1; e <= kLongRunCollisions; ++e) {
    Collision got{};
    if (!own_step(t, got, e)) return;
    int i = -1, j = -1, w = -1;
    const double overlap = billiard::testing::worst_overlap(t.c, t.a, &i, &j);
    const double protrusion = billiard::testing::worst_protrusion(t.c, t.R, t.a, &w);
    if (!(overlap <= 1e-9)) {
      ADD_FAILURE() << explain("no two circles to overlap (by more than 1e-9) at any collision",
                               text("after collision ", e, " (", describe_collision(got), ") circles ", i, " and ", j,
                                    " overlap by ", overlap),
                               "a pair that passes through each other was never tested: check the 3x3 block of "
                               "cells, the crossings before the earliest collision, and the cell lists after them.");
      return;
    }
    if (!(protrusion <= 1e-9)) {
      ADD_FAILURE() << explain("every circle to stay on the table at every collision",
                               text("after collision ", e, " (", describe_collision(got), ") circle ", w,
                                    " sticks out by ", protrusion),
                               kHintWall);
      return;
    }
  }
}

GRADED_TEST(Sectors, NoImmediateRepeatOfTheSameCollision, 2, after_due_date) {
  SectorTable t = long_run_table();
  const double scale = billiard::testing::sector_time_scale(t);
  Collision previous{-1, -1, -2};
  for (int e = 1; e <= kLongRunCollisions; ++e) {
    Collision got{};
    if (!own_step(t, got, e)) return;
    const bool same = got.other == kWall ? is_wall(previous, got.circle) : is_pair(previous, got.circle, got.other);
    if (same && got.time <= 1e-9 * scale) {
      ADD_FAILURE() << explain(text("a different event after ", describe_collision(previous)),
                               text("collision ", e, " repeated it: ", describe_collision(got)),
                               "pair_time already rejects pairs moving apart; for the wall, as in propagate, only a "
                               "circle moving outward (r.v > 0) can hit it at t = 0.");
      return;
    }
    previous = got;
  }
}

// ---------------------------------------------------------------------------------------------
// 5. Efficiency: counted with pair_time_calls() for the hint, then timed from outside on
// tables where all pairs cannot keep up.

// Dilute tables: n circles of radius 0.5 at about 3% of the table, cell_size = 2a = 1.
SectorTable dilute_table(int n, std::uint64_t seed) {
  const double a = 0.5;
  const double R = a * std::sqrt(n / 0.03);
  return SectorTable{R, a, 2 * a, billiard::testing::scattered_circles(R, a, n, seed),
                     billiard::testing::gaussian_velocities(n, seed + 7)};
}

// Pair tests of one call on each of `tables` seeds (summed), or -1 after reporting a refused
// call; each call starts from a fresh state.
long long count_pair_tests(int n, int tables, std::uint64_t seed) {
  long long total = 0;
  for (int k = 0; k < tables; ++k) {
    SectorTable t = dilute_table(n, seed + static_cast<std::uint64_t>(k));
    const long long before = billiard::pair_time_calls();
    try {
      billiard::testing::recorded_sectors_step(t.R, t.a, t.n(), t.c, t.v, t.cell);
    } catch (const std::invalid_argument& error) {
      ADD_FAILURE() << explain(text("propagate_sectors to step a valid table of ", n, " circles"),
                               text("it threw std::invalid_argument: \"", error.what(), "\""), kHintSameAsPropagate);
      return -1;
    }
    total += billiard::pair_time_calls() - before;
  }
  return total;
}

constexpr int kLargeCircles = 200000;

// A dilute table of kLargeCircles circles of radius 0.5 (about 3% covered), built in O(n): one
// circle in each square of a lattice inside the table, jittered within its square, the rows in
// random order.
SectorTable large_dilute_table(std::uint64_t seed) {
  const double a = 0.5, spacing = 10 * a;
  std::mt19937_64 rng(seed);
  const double R = spacing * (std::sqrt(kLargeCircles / 3.14159265358979) + 2);
  const double inner = R - a - spacing;  // a square's centre this close to the origin keeps its circle on the table
  std::vector<std::pair<double, double>> sites;
  const int across = static_cast<int>(R / spacing);
  for (int ix = -across; ix <= across; ++ix) {
    for (int iy = -across; iy <= across; ++iy) {
      const double x = ix * spacing, y = iy * spacing;
      if (x * x + y * y <= inner * inner) sites.emplace_back(x, y);
    }
  }
  std::shuffle(sites.begin(), sites.end(), rng);
  sites.resize(kLargeCircles);
  std::uniform_real_distribution<double> jitter(-(spacing / 2 - a), spacing / 2 - a);
  Coordinates c(kLargeCircles, 2);
  for (int i = 0; i < kLargeCircles; ++i) {
    c(i, 0) = sites[static_cast<std::size_t>(i)].first + jitter(rng);
    c(i, 1) = sites[static_cast<std::size_t>(i)].second + jitter(rng);
  }
  return SectorTable{R, a, 2 * a, c, billiard::testing::gaussian_velocities(kLargeCircles, seed + 7)};
}

// Steps a large dilute table from a fresh state and compares the first collision with the
// library's. Said before the step, so that a student whose test is stopped at its time limit
// reads why. (All pairs cost n / 2 pair tests per circle, the cells a few: at this size, even
// vectorised, far more than the ten times the reference's time that the limit allows.)
void expect_large_table_stepped(std::uint64_t seed) {
  std::cout << "Next: one step on a dilute table of " << kLargeCircles
            << " circles (cell_size = 2a), within this test's time limit. The cells need a few pair tests per circle "
               "there; all pairs are "
            << static_cast<double>(kLargeCircles) * (kLargeCircles - 1) / 2
            << ", which do not finish in time (if this test was stopped, that is why)." << std::endl;
  const SectorTable t = large_dilute_table(seed);
  first_collision_is_the_librarys(t, text("dilute table of ", kLargeCircles, " circles (R = ", t.R, ", a = ", t.a,
                                          ", cell_size = 2a)"),
                                  false);
}

const char* const kHintUsePairTime =
    "call the provided pair_time(circle_radius, coordinates, velocities, i, j) for every pair you test, instead of "
    "your own formula: the tests count its calls to measure how many pairs you test (without a clock).";
const char* const kHintFewerPairs =
    "test only the pairs in the 3x3 block of cells around each circle, plus the new neighbours after each crossing "
    "before the earliest collision; testing all pairs (or all pairs after each crossing) costs n (n - 1) / 2 per "
    "call.";

// Whether the pair tests per call on dilute tables of 1000 circles are at least `factor` times
// fewer than all pairs; reports why not.
bool fewer_pairs(long long factor) {
  const int n = 1000, tables = 3;
  const long long calls = count_pair_tests(n, tables, 8100);
  if (calls < 0) return false;
  if (calls == 0) {
    ADD_FAILURE() << explain("some calls of pair_time in three steps of dilute tables of 1000 circles",
                             "pair_time was never called, so your pair tests cannot be counted", kHintUsePairTime);
    return false;
  }
  const long long all_pairs = static_cast<long long>(n) * (n - 1) / 2;
  const double per_call = static_cast<double>(calls) / tables;
  if (per_call * static_cast<double>(factor) > static_cast<double>(all_pairs)) {
    ADD_FAILURE() << explain(text("at most n (n - 1) / 2 / ", factor, " = ", all_pairs / factor,
                                  " pair tests per call on dilute tables of 1000 circles (3% covered, cell_size = 2a)"),
                             text(per_call, " pair tests per call (", static_cast<double>(all_pairs) / per_call,
                                  " times fewer than all pairs)"),
                             kHintFewerPairs);
    return false;
  }
  return true;
}

// Whether 4 times the circles at the same density take at most 8 times the pair tests (linear
// growth is 4 times, all pairs 16 times); reports why not.
bool pair_tests_grow_about_linearly() {
  const long long small = count_pair_tests(500, 4, 8200);
  const long long large = count_pair_tests(2000, 4, 8300);
  if (small < 0 || large < 0) return false;
  if (small == 0 || large == 0) {
    ADD_FAILURE() << explain("pair tests counted through pair_time", "pair_time was never called", kHintUsePairTime);
    return false;
  }
  const double ratio = static_cast<double>(large) / static_cast<double>(small);
  if (!(ratio < 8.0)) {
    ADD_FAILURE() << explain(
        "at most 8 times the pair tests for 4 times the circles at the same density (linear growth gives ~4, all "
        "pairs 16)",
        text(small, " pair tests for 500 circles and ", large, " for 2000: ", ratio, " times as many"), kHintFewerPairs);
    return false;
  }
  return true;
}

// The count gives the hint; the points need the large table too (see the top of this file).
GRADED_TEST(Sectors, TestsAtLeast20TimesFewerPairsThanAllPairs, 4, visible) {
  if (fewer_pairs(20)) expect_large_table_stepped(8150);
}

GRADED_TEST(Sectors, TestsAtLeast100TimesFewerPairsGrowingLinearlyWithN, 4, after_due_date) {
  if (fewer_pairs(100) && pair_tests_grow_about_linearly()) expect_large_table_stepped(8350);
}

// ---------------------------------------------------------------------------------------------
// 6. Invalid arguments: named in the message, state unchanged.

using billiard::testing::expect_invalid_argument;

// A valid table for the argument checks.
SectorTable valid_table() { return table(10, 1, 2, {-5, 0, 1, 0, 5, 0, -1, 0, 0, 4, 0, 0.5}); }

// Expects std::invalid_argument naming `argument` and the state left as it was.
void expect_refused(SectorTable t, double R, double a, int n, double cell, const std::string& situation,
                    const std::string& argument, const std::string& hint) {
  const SectorTable before = t;
  expect_invalid_argument([&] { billiard::propagate_sectors(R, a, n, t.c, t.v, cell); }, situation, argument, hint);
  const bool same = t.c.rows() == before.c.rows() && t.v.rows() == before.v.rows() && t.c == before.c && t.v == before.v;
  EXPECT_TRUE(same) << explain(text("coordinates and velocities unchanged after refusing ", situation),
                               "they were changed", "check every argument before changing anything.");
}

GRADED_TEST(Sectors, RejectsCellSmallerThanADiameter, 1, after_due_date) {
  SectorTable t = valid_table();
  for (const double cell : {1.99, 1.0, 0.0, -2.0}) {
    expect_refused(t, 10, 1, 3, cell, text("cell_size = ", cell, " with circle_radius = 1"), "cell_size",
                   "call checks::cell_size(table_radius, circle_radius, cell_size): cells smaller than 2a would miss "
                   "touching circles two cells apart.");
  }
}

GRADED_TEST(Sectors, RejectsNonFiniteCellSize, 1, after_due_date) {
  SectorTable t = valid_table();
  for (const double cell : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    expect_refused(t, 10, 1, 3, cell, text("cell_size = ", cell), "cell_size",
                   "call checks::cell_size(...): NaN fails every comparison, so `cell_size < 2a` alone lets it in.");
  }
}

GRADED_TEST(Sectors, RejectsTooManyCells, 1, after_due_date) {
  // 2R / cell_size = 20 / 0.002 = 10000 cells across, more than the 4096 allowed.
  SectorTable t = table(10, 0.001, 0.002, {-5, 0, 1, 0, 5, 0, -1, 0});
  expect_refused(t, 10, 0.001, 2, 0.002, "cell_size = 0.002 on a table of radius 10 (10000 cells across)", "cell_size",
                 "call checks::cell_size(...): it refuses more than 4096 cells across, which would not fit in memory.");
}

GRADED_TEST(Sectors, RejectsBadRadii, 1, after_due_date) {
  SectorTable t = valid_table();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double R : {0.0, -10.0, nan}) {
    expect_refused(t, R, 1, 3, 2, text("table_radius = ", R), "table_radius", "call checks::table(...) first.");
  }
  for (const double a : {0.0, -1.0, nan, 10.0}) {
    expect_refused(t, 10, a, 3, 30, text("circle_radius = ", a), "circle_radius", "call checks::table(...) first.");
  }
}

GRADED_TEST(Sectors, RejectsRowCountMismatch, 1, after_due_date) {
  SectorTable t = valid_table();
  SectorTable fewer = t;
  fewer.c.conservativeResize(2, 2);
  expect_refused(fewer, 10, 1, 3, 2, "coordinates with 2 rows for n = 3", "coordinates",
                 "call checks::rows(coordinates, n, \"coordinates\").");
  SectorTable more = t;
  more.v.conservativeResize(4, 2);
  more.v.row(3) << 1, 1;
  expect_refused(more, 10, 1, 3, 2, "velocities with 4 rows for n = 3", "velocities",
                 "call checks::rows(velocities, n, \"velocities\").");
  expect_refused(t, 10, 1, -1, 2, "n = -1", "n", "call checks::table(...), which refuses n < 0.");
}

GRADED_TEST(Sectors, RejectsOverlappingOrEscapedCircles, 1, after_due_date) {
  SectorTable overlapping = table(10, 1, 2, {0, 0, 1, 0, 1.5, 0, -1, 0});
  expect_refused(overlapping, 10, 1, 2, 2, "two circles 1.5 apart with circle_radius = 1", "coordinates",
                 "call checks::placement(table_radius, circle_radius, coordinates), as in propagate.");
  SectorTable outside = table(10, 1, 2, {9.5, 0, 1, 0});
  expect_refused(outside, 10, 1, 1, 2, "a circle at (9.5, 0) on a table R = 10 with circle_radius = 1",
                 "coordinates", "call checks::placement(table_radius, circle_radius, coordinates), as in propagate.");
}

GRADED_TEST(Sectors, RejectsNoCirclesAndAllCirclesAtRest, 1, after_due_date) {
  SectorTable none{10, 1, 2, Coordinates(0, 2), Velocities(0, 2)};
  expect_refused(none, 10, 1, 0, 2, "n = 0 (no collision ever)", "",
                 "with no event at all, throw std::invalid_argument as propagate does.");
  SectorTable resting = valid_table();
  resting.v.setZero();
  expect_refused(resting, 10, 1, 3, 2, "all circles at rest (no collision ever)", "",
                 "circles at rest never cross a face nor reach the wall: with no event at all, throw "
                 "std::invalid_argument instead of looping or returning an infinite time.");
}

}  // namespace
