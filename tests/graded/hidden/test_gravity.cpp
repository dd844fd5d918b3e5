// Instructor-only graded tests of task 7 (gravity), hidden from students: left out of the
// student release, and the grader shows neither their names nor their feedback. They hold out
// cases a solution cannot be tuned to: tables with their own seeds compared step by step with
// the library, near-grazing arcs in random directions, and a long run under tilted gravity.
//
// Tolerances as in the visible suite (see its top comment and gravity_support.hpp): 1e-9 for
// rounding, plus the first-order effect of the library's wall contact slack.
#include "graded/gravity_support.hpp"

#include "time_of_impact.hpp"
#include "support/graded.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

namespace {

using billiard::Collision;
using billiard::kWall;
using billiard::Vector;
using billiard::testing::describe_collision;
using billiard::testing::explain;
using billiard::testing::GravityTable;
using billiard::testing::text;

// Calls the student's step; a refusal of a valid state is a failure.
bool student_step(GravityTable& t, Collision& got, const std::string& where) {
  try {
    got = billiard::testing::recorded_gravity_step(t.R, t.a, t.n(), t.c, t.v, t.g);
    return true;
  } catch (const std::exception& error) {
    ADD_FAILURE() << explain(text(where, ": the next event"), text("propagate_gravity threw: ", error.what()),
                             "a valid state under gravity always has a next event.");
    return false;
  }
}

GRADED_TEST(Gravity, UnseenTablesAgreeWithTheEngine, 3, hidden) {
  // 16 random tables and 8 crowded ones with seeds of their own, 40 steps each.
  for (int k = 0; k < 24; ++k) {
    std::string label;
    GravityTable t = billiard::testing::random_gravity_table(0x5eed00ULL + static_cast<std::uint64_t>(k) * 13, k >= 16,
                                                             label);
    for (int e = 0; e < 40; ++e) {
      billiard::testing::tidy_for_library(t);
      const auto lib = billiard::testing::library_step(t);
      ASSERT_TRUE(lib.ok) << "test error at " << label << ", step " << e << ": " << lib.problem;
      GravityTable mine = t;
      Collision got{};
      const std::string where = text("held-out ", label, ", step ", e);
      if (!student_step(mine, got, where)) return;
      const std::string problem = billiard::testing::compare_with_library(
          t, got, mine, lib, where, "find the earliest wall or pair event.", "move every circle on its parabola.",
          "reflect the velocity at contact.", "exchange the normal components at contact.");
      if (!problem.empty()) {
        ADD_FAILURE() << problem;
        return;
      }
      t.c = lib.c;
      t.v = lib.v;
    }
  }
}

GRADED_TEST(Gravity, RandomNearGrazingArcsFindTheirFirstHit, 2, hidden) {
  // Arcs whose apex lies eps = 1e-9 to 1e-6 (relative) beyond the wall, for gravity in random
  // directions and apexes up to 0.3 rad off the top: the circle is outside only briefly. The
  // time comes from the library's quartic solver; cases where the first hit is not the graze
  // (the arc met the wall earlier) are skipped, and at least 30 of 70 must remain.
  std::mt19937_64 rng(0x6a2eULL);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 70; ++k) {
    const double R = 5 + 20 * unit(rng);
    const double a = R * (0.05 + 0.2 * unit(rng));
    const double L = R - a;
    const double strength = 0.1 + 3 * unit(rng);
    const double up = 2 * std::acos(-1.0) * unit(rng);  // the direction against gravity
    const Vector u(std::cos(up), std::sin(up));
    const Vector side(-u(1), u(0));
    const double off = 0.3 * (2 * unit(rng) - 1);
    const double eps = L * std::pow(10.0, -9 + 3 * unit(rng));
    const Vector apex = (L + eps) * (std::cos(off) * u + std::sin(off) * side);
    // Apex speed across gravity below sqrt(|g| L): the arc bends faster than the wall there.
    const double across = std::sqrt(strength * L) * (0.2 + 0.6 * unit(rng));
    const Vector g = -strength * u;
    const double T = across * (0.5 + unit(rng)) / strength;  // time from the start to the apex
    GravityTable t;
    t.R = R;
    t.a = a;
    t.g = g;
    t.c.resize(1, 2);
    t.v.resize(1, 2);
    const Vector v_apex = across * side;
    t.c.row(0) = apex - T * v_apex + (T * T / 2) * g;
    t.v.row(0) = v_apex - T * g;
    if (!(t.c.row(0).norm() < L)) continue;
    const double expected = billiard::disc_in_circle_time(t.c.row(0), t.v.row(0),
                                                          t.g, L);
    if (!(std::abs(expected - T) <= 0.05 * T)) continue;  // met the wall before the graze
    ++checked;
    Collision got{};
    const std::string where = text("near-grazing arc ", k);
    if (!student_step(t, got, where)) return;
    if (!(got.other == kWall && std::abs(got.time - expected) <= 1e-9 * (expected + R / across))) {
      ADD_FAILURE() << explain(text(where, ": the wall hit after time ", expected), text("returned ", describe_collision(got)),
                               "find the first upward crossing of the quartic, even when the arc is outside only "
                               "briefly.");
      return;
    }
  }
  EXPECT_GE(checked, 30) << "test error: too few near-grazing arcs were generated";
}

GRADED_TEST(Gravity, TiltedLongRunKeepsEnergyAndStaysInside, 2, hidden) {
  // 25 circles, gravity (-0.6, -0.8) of strength 2, 1500 events on the student's own trajectory.
  GravityTable t;
  t.R = 12;
  t.a = 0.6;
  t.c = billiard::testing::scattered_circles(t.R, t.a, 25, 0xfa11ULL);
  t.v = billiard::testing::gaussian_velocities(25, 0xfa11ULL) * 1.5;
  t.g << -1.2, -1.6;
  const long double start = billiard::testing::energy_per_circle(t);
  const double scale = billiard::testing::energy_scale(t);
#ifdef NDEBUG
  const int events = 1500;
#else
  const int events = 200;
#endif
  for (int e = 1; e <= events; ++e) {
    Collision got{};
    if (!student_step(t, got, text("tilted long run, event ", e))) return;
    const double drift = static_cast<double>(std::abs(billiard::testing::energy_per_circle(t) - start)) / scale;
    const double overlap = billiard::testing::worst_overlap(t.c, t.a);
    const double protrusion = billiard::testing::worst_protrusion(t.c, t.R, t.a);
    if (!(drift <= 1e-9 && overlap <= 1e-9 && protrusion <= 1e-9)) {
      ADD_FAILURE() << explain("energy constant to 1e-9, no overlaps, every circle on the table",
                               text("after event ", e, ": energy change ", drift, ", overlap ", overlap,
                                    ", protrusion ", protrusion),
                               "conserve energy and never miss an event.");
      return;
    }
  }
}

}  // namespace
