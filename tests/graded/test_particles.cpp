// Task particles (the C track): the "Collisions" program, graded by its output. Each test runs
// your program (tasks/particles.c) on one file and compares with the project's particles
// command: positions within 1e-6, collision counts exactly, the format exactly. The files are
// small and the tests come in the order of the steps in tasks/particles.c, so the first one that
// fails points at the step to fix. Run one yourself: build/tasks/tasks/particles FILE END_TIME.
#include "particles_support.hpp"
#include "support/graded.hpp"

namespace {

using particles_grading::expect_same_output;

// Steps 2 and 5: one particle bouncing between the walls, moved on to END_TIME after its last
// collision; every line printed by printf as asked.
GRADED_TEST(Particles, OneParticleBetweenWalls, 2, visible) {
  expect_same_output("one_particle",
                     "1\n0.5\n10 6\n2 3 1.5 0.4\n", "13.3",
                     "a particle meets the wall x = Lx when its centre reaches Lx - R: after (Lx - R - x) / u for "
                     "u > 0 and (R - x) / u for u < 0, the same along y; reverse only the velocity component normal "
                     "to that wall and count one wall collision",
                     particles_grading::kAdvanceHint);
}

// Step 2: a particle that reaches a corner hits both walls at the same instant.
GRADED_TEST(Particles, CornerCountsTwoWallCollisions, 2, visible) {
  expect_same_output("corner", "1\n0.5\n10 6\n2 2 -1 -1\n", "3",
                     "a particle reaching a corner hits both walls at the same instant: two wall collisions (after "
                     "the first, its entry is recomputed and the other wall follows at once, at time 0 from now)");
}

// Step 4: two particles that never meet, each between its walls: their wall collisions must be
// taken in time order, so the array must stay sorted after every update.
GRADED_TEST(Particles, WallCollisionsInTimeOrder, 2, visible) {
  expect_same_output("two_columns", "2\n0.5\n10 6\n2 3 0 1\n7 2 0 -1.7\n", "9.1",
                     "process the collisions in time order: the earliest one must come first after every update. "
                     "Check your insertion sort: each entry moves left past every later one, down to index 0");
}

// Step 3: a head-on pair that meets once before END_TIME, far from the walls.
GRADED_TEST(Particles, HeadOnPairMeetsAtTheSmallerRoot, 2, visible) {
  expect_same_output("head_on_once", "2\n0.5\n10 6\n3 3 1 0\n7 3 -1 0\n", "2",
                     "two particles touch first at the smaller root t = (-b - sqrt(b^2 - a c)) / a of "
                     "a t^2 + 2 b t + c = 0 (a = dv.dv, b = dr.dv, c = dr.dr - (2R)^2), only if b < 0 and "
                     "b^2 - a c >= 0; then they exchange their whole velocities");
}

// Step 4: the same pair for longer: after meeting, both go to the walls and meet again.
GRADED_TEST(Particles, HeadOnPairThenWalls, 2, visible) {
  expect_same_output("head_on_walls", "2\n0.5\n10 6\n3 3 1 0\n7 3 -1 0\n", "12",
                     "after a collision between two particles, recompute every pending collision of both particles "
                     "(the wall of each, and every pair with either of them): both velocities changed");
}

// The three examples of tests/particles/examples, with the same END_TIME as their .expected files.
GRADED_TEST(Particles, ExampleHeadOn, 2, visible) {
  expect_same_output("head_on", "2\n1\n20 10\n5 5 1 0\n15 5 -1 0\n", "5",
                     "compare with the visible tests above: the first of them that fails names the step to fix");
}

GRADED_TEST(Particles, ExampleOblique, 2, visible) {
  expect_same_output("oblique", "2\n1\n20 10\n5 5 1 0.5\n7 6.5 0 0\n", "3",
                     "particles exchange their WHOLE velocities (u and v), also when they meet at an angle");
}

GRADED_TEST(Particles, ExampleThree, 2, visible) {
  expect_same_output("three", "3\n0.5\n10 6\n1 1 -1 -1\n5 3 1 0.5\n8 3 -1 0\n", "4",
                     "compare with the visible tests above: the first of them that fails names the step to fix");
}

}  // namespace
