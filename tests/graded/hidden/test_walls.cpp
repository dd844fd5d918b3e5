// Instructor-only graded tests of task 8 (`propagate_walls`), hidden from students: left out of
// the student release, and the grader shows neither their names nor their feedback. They hold
// out wall layouts a student cannot tune a solution to: random tables with their own seeds,
// compared step by step with the finished library from shared states, and a long run in a
// layout of their own.
//
// Tolerances as in the visible suite (walls_support.hpp): 1e-9 relative per step, far above
// rounding (~1e-15) and far below any real mistake.
#include "graded/walls_support.hpp"
#include "support/fixtures.hpp"
#include "support/graded.hpp"
#include "support/student_messages.hpp"

#include <cmath>
#include <string>

namespace {

using billiard::Collision;
using billiard::testing::explain;
using billiard::testing::text;

std::string held_out_hint(const std::string& what, bool wall_event) {
  (void)wall_event;
  return what == "event" ? "compare every event time and return the smallest." : "check the step's formulas.";
}

GRADED_TEST(Walls, HeldOutWallLayoutsAgreeWithTheEngine, 3, hidden) {
  // 30 random tables of every layout, with seeds of their own; 80 steps each.
  for (int k = 0; k < 30; ++k) {
    if (!billiard::testing::matches_library(billiard::testing::random_wall_table(k, 0x5eedULL), 80, held_out_hint)) return;
  }
}

GRADED_TEST(Walls, HeldOutPenStaysClosed, 2, hidden) {
  // A pen: a square of four walls whose corners meet, one corner on the rim's side and a gate
  // of zero length in the middle; circles inside and outside. 1500 events: nobody changes
  // sides, nobody comes closer than circle_radius to a wall.
  billiard::testing::WallTable t;
  t.R = 8;
  t.a = 0.4;
  t.walls = {billiard::testing::wall(-4, -4, 4, -4), billiard::testing::wall(4, -4, 4, 4),
             billiard::testing::wall(4, 4, -4, 4), billiard::testing::wall(-4, 4, -4, -4),
             billiard::testing::wall(0, 0, 0, 0)};
  auto inside = [](const billiard::Vector& p) { return std::abs(p(0)) < 4 && std::abs(p(1)) < 4; };
  t.c = billiard::testing::place_circles(t.R, t.a, 20, t.walls, 0xbeefULL);
  t.v = billiard::testing::gaussian_velocities(t.n(), 0xbeefULL) * 3.0;
  std::vector<bool> was_inside;
  for (int c = 0; c < t.n(); ++c) was_inside.push_back(inside(t.c.row(c)));
  for (int e = 0; e < 1500; ++e) {
    Collision got{};
    try {
      got = billiard::testing::recorded_walls_step(t.R, t.a, t.n(), t.c, t.v, t.walls);
    } catch (const std::exception& error) {
      ADD_FAILURE() << explain(text("step ", e, ": the next collision"), text("it threw: ", error.what()),
                               "a valid table must never be refused.");
      return;
    }
    for (int c = 0; c < t.n(); ++c) {
      double closest = 1e300;
      for (const auto& w : t.walls) closest = std::min(closest, billiard::testing::segment_distance(t.c.row(c), w));
      if (inside(t.c.row(c)) != was_inside[static_cast<std::size_t>(c)] || !(closest >= t.a - 1e-9)) {
        ADD_FAILURE() << explain(text("step ", e, ": circle ", c, " to stay on its side of the pen's walls"),
                                 text("it is at ", billiard::testing::row(t.c, c), ", ", closest, " from a wall"),
                                 "no circle may pass through or into a wall.");
        return;
      }
    }
  }
}

}  // namespace
