// Helpers shared by the graded suite of task 7 (gravity) and its hidden tests: tables under
// gravity, one step of the finished library (billiard::Simulation) from a given state, and the
// comparison of a student's step with it.
//
// The library is an independent implementation of the same physics, with one documented
// difference: under gravity it lets a circle meet the table wall billiard::kFixedContactSlack
// = 1e-10 of its radius beyond touching (settings.hpp), so that a circle resting on the
// wall cannot bounce for ever at one instant. A wall hit there happens a time
// dt = 1e-10 a / v_n later (v_n the normal speed at contact), which moves every circle by up to
// v dt and turns the wall normal a little. The comparison allows for twice these first-order
// shifts on top of 1e-9 for rounding; away from grazing hits they are far below 1e-9.
#pragma once

#include "billiard/engine/simulation.hpp"
#include "billiard/extensions.hpp"
#include "support/failure_pictures.hpp"
#include "support/fixtures.hpp"
#include "support/student_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>

namespace billiard::testing {

// The student's propagate_gravity, recorded for the pictures of a failing case.
inline Collision recorded_gravity_step(double R, double a, int n, Coordinates& c, Velocities& v, const Vector& g) {
  return recorded_step(table_board(R, a, {}, g), c, v, [&] { return propagate_gravity(R, a, n, c, v, g); });
}

// A table of n circles under gravity g.
struct GravityTable {
  double R = 10;
  double a = 1;
  Coordinates c;
  Velocities v;
  Vector g = Vector::Zero();
  int n() const { return static_cast<int>(c.rows()); }
};

inline std::string describe_pair_or_wall(int circle, int other) {
  return other == kWall ? text("circle ", circle, " with the wall") : text("circles ", circle, " and ", other);
}

inline bool same_collision(int circle, int other, const Collision& got) {
  if (other == kWall) return got.other == kWall && got.circle == circle;
  return (got.circle == circle && got.other == other) || (got.circle == other && got.other == circle);
}

// The energy per circle, (1/n) sum (|v|^2 / 2 - g.r), in long double: the tests' own value.
inline long double energy_per_circle(const GravityTable& t) {
  long double sum = 0;
  for (int i = 0; i < t.n(); ++i) {
    const long double vx = t.v(i, 0), vy = t.v(i, 1);
    sum += (vx * vx + vy * vy) / 2 - static_cast<long double>(t.g(0)) * t.c(i, 0) -
           static_cast<long double>(t.g(1)) * t.c(i, 1);
  }
  return t.n() == 0 ? 0 : sum / t.n();
}

// The size of the terms that make up the energy, (1/n) sum (|v|^2 / 2 + |g| |r|): relative
// drifts are measured against it (the energy itself may be near zero).
inline double energy_scale(const GravityTable& t) {
  double sum = 0;
  for (int i = 0; i < t.n(); ++i) sum += t.v.row(i).squaredNorm() / 2 + t.g.norm() * t.c.row(i).norm();
  return t.n() == 0 ? 0 : sum / t.n();
}

// Pulls circles that rounding left a hair outside the wall back onto it, and pairs overlapping
// by rounding apart, by ~1e-15 of the table: the library accepts only states without any
// overlap. The physics does not change at that scale; the student's code gets the same state.
inline void tidy_for_library(GravityTable& t) {
  const double reach = t.R - t.a;
  const double diameter = 2 * t.a;
  for (int pass = 0; pass < 20; ++pass) {
    bool changed = false;
    for (int i = 0; i < t.n(); ++i) {
      const double distance = t.c.row(i).norm();
      if (distance > reach) {
        double scale = reach / distance;
        while (t.c.row(i).norm() * scale > reach) scale = std::nextafter(scale, 0.0);
        t.c.row(i) *= scale;
        changed = true;
      }
    }
    for (int i = 0; i < t.n(); ++i) {
      for (int j = i + 1; j < t.n(); ++j) {
        const Vector d = t.c.row(j) - t.c.row(i);
        if (d.squaredNorm() < diameter * diameter) {
          const double push = (diameter - d.norm()) / 2 + 4e-16 * t.R * (pass + 1);
          const Vector normal = d.normalized();
          t.c.row(i) -= push * normal;
          t.c.row(j) += push * normal;
          changed = true;
        }
      }
    }
    if (!changed) return;
  }
}

// One step of the library from the state of `t`.
struct LibraryStep {
  bool ok = false;
  std::string problem;  // why the library could not step (a test-side problem), if !ok
  double time = 0;
  int circle = -1;
  int other = kWall;
  Coordinates c;
  Velocities v;
};

inline LibraryStep library_step(const GravityTable& t) {
  LibraryStep s;
  try {
    Settings settings;
    settings.gravity = Vector(t.g(0), t.g(1));
    Simulation sim(circular_table(t.R), settings);
    const Coordinates positions = t.c;
    const Velocities velocities = t.v;
    sim.add_discs(positions, velocities, t.a);
    sim.set_log_events(true);
    const AdvanceResult result = sim.advance(1);
    if (result.collisions != 1 || sim.event_log().empty()) {
      s.problem = text("the library found no event (", result.stuck_reason, ")");
      return s;
    }
    const EventRecord& e = sim.event_log().front();
    s.time = e.time;
    s.circle = e.disc;
    s.other = e.kind == EventKind::DiscWall ? kWall : e.other;
    const State state = sim.current_state();
    s.c = state.positions;
    s.v = state.velocities;
    s.ok = true;
  } catch (const std::exception& error) {
    s.problem = text("the library refused the state: ", error.what());
  }
  return s;
}

// The delay the library's wall slack causes for a wall hit of circle i in the state after it:
// 1e-10 a over the normal speed.
inline double slack_delay(double a, const Coordinates& c, const Velocities& v, int i) {
  const double normal_speed = std::abs(v.row(i).dot(c.row(i).normalized()));
  return kFixedContactSlack * a / std::max(normal_speed, 1e-300);
}

// Compares the student's step (got, leading from `before` to `after`) with the library's from
// the same state. Returns "" when they agree, else a failure message for the student. A
// different event is accepted when the two happen at the same time within the tolerance and
// the student's is a real contact (two events at once: either order is right).
inline std::string compare_with_library(const GravityTable& before, const Collision& got, const GravityTable& after,
                                        const LibraryStep& lib, const std::string& where,
                                        const std::string& hint_event, const std::string& hint_motion,
                                        const std::string& hint_wall_velocity, const std::string& hint_pair_velocity) {
  const double L = before.R - before.a;
  double speed = std::sqrt(before.g.norm() * before.R);
  for (int i = 0; i < lib.v.rows(); ++i) speed = std::max(speed, lib.v.row(i).norm());
  const double tau = before.R / speed;  // time to cross the table at the top speed
  // The slack's delay is tiny at any real contact; at a grazing one (or at a wall "hit" the
  // student's code reports away from the wall) it would grow without bound, and with it the
  // tolerances: 1e-6 of tau bounds it far above real delays.
  double delay = lib.other == kWall ? std::min(slack_delay(before.a, lib.c, lib.v, lib.circle), 1e-6 * tau) : 0.0;
  const bool student_wall = got.other == kWall && got.circle >= 0 && got.circle < after.n();
  if (student_wall) delay = std::max(delay, std::min(slack_delay(before.a, after.c, after.v, got.circle), 1e-6 * tau));
  const double time_tolerance = 1e-9 * (lib.time + tau) + 2 * delay;
  const double position_tolerance = 1e-9 * before.R + 2 * delay * speed;
  const double velocity_tolerance = 1e-9 * speed + 2 * delay * (before.g.norm() + 2 * speed * speed / L);
  const std::string expected_event =
      text(describe_pair_or_wall(lib.circle, lib.other), " after time ", lib.time);

  if (!same_collision(lib.circle, lib.other, got)) {
    bool contact = false;
    if (student_wall) {
      contact = std::abs(after.c.row(got.circle).norm() - L) <= position_tolerance;
    } else if (got.circle >= 0 && got.other >= 0 && got.circle < after.n() && got.other < after.n()) {
      contact = std::abs((after.c.row(got.circle) - after.c.row(got.other)).norm() - 2 * before.a) <=
                position_tolerance;
    }
    if (contact && std::abs(got.time - lib.time) <= time_tolerance) return "";  // a tie
    return explain(text("at ", where, ": the earliest event, ", expected_event),
                   text("returned ", describe_collision(got)), hint_event);
  }
  if (!(std::abs(got.time - lib.time) <= time_tolerance)) {
    return explain(text("at ", where, ": ", expected_event, " (within ", time_tolerance, ")"),
                   text("returned ", describe_collision(got)), hint_event);
  }
  for (int i = 0; i < before.n(); ++i) {
    if (!((after.c.row(i) - lib.c.row(i)).norm() <= position_tolerance)) {
      return explain(text("at ", where, ": after ", expected_event, ", circle ", i, " at ", row(lib.c, i),
                          " (within ", position_tolerance, ")"),
                     text("it is at ", row(after.c, i), " (it started at ", row(before.c, i), " with velocity ",
                          row(before.v, i), ", g = (", before.g(0), ", ", before.g(1), "))"),
                     hint_motion);
    }
  }
  for (int i = 0; i < before.n(); ++i) {
    if (!((after.v.row(i) - lib.v.row(i)).norm() <= velocity_tolerance)) {
      const bool colliding = i == lib.circle || i == lib.other;
      return explain(text("at ", where, ": after ", expected_event, ", circle ", i, " with velocity ", row(lib.v, i),
                          " (within ", velocity_tolerance, ")"),
                     text("its velocity is ", row(after.v, i), " (before the step ", row(before.v, i), ")"),
                     !colliding ? hint_motion : lib.other == kWall ? hint_wall_velocity : hint_pair_velocity);
    }
  }
  return "";
}

// A random table under gravity, from the fixtures only (never from the student's code): n
// circles of radius a on a table of radius R, Gaussian velocities times a speed, every fifth
// table with half its circles at rest, and g of random direction and a strength from weak
// (the circles barely bend, |g| R = v^2 / 100) to strong (|g| R = 100 v^2).
inline GravityTable random_gravity_table(std::uint64_t seed, bool crowded, std::string& label) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double radii[] = {1.0, 10.0, 3.7, 100.0};
  const double speeds[] = {0.01, 1.0, 30.0};
  const auto k = static_cast<int>(seed % 60);
  GravityTable t;
  t.R = radii[k % 4];
  const int n = crowded ? 15 + k % 16 : 1 + k % 12;
  const double fraction = crowded ? 0.2 + 0.1 * unit(rng) : 0.01 + (n >= 5 ? 0.19 : 0.09) * unit(rng);
  t.a = std::min(t.R * std::sqrt(fraction / n), 0.5 * t.R);
  t.c = scattered_circles(t.R, t.a, n, seed);
  t.v = gaussian_velocities(n, seed + 1) * speeds[k % 3];
  if (k % 5 == 0 && n > 1) {
    for (int i = 0; i < n; i += 2) t.v.row(i).setZero();
  }
  const double angle = 2 * std::acos(-1.0) * unit(rng);
  const double strength = std::pow(10.0, 4 * unit(rng) - 2) * speeds[k % 3] * speeds[k % 3] / t.R;
  t.g << strength * std::cos(angle), strength * std::sin(angle);
  label = text(crowded ? "crowded" : "random", " table ", seed, " (n = ", n, ", R = ", t.R, ", a = ", t.a, ", g = (",
               t.g(0), ", ", t.g(1), "))");
  return t;
}

// The judge of the pictures of a failing case (failure_pictures.hpp): the library's step from
// the board (tidied as the tests tidy their tables), compared as compare_with_library does.
inline Judgement gravity_judgement(const Board& board, const Outcome& got) {
  GravityTable before{board.table_radius, board.circle_radius, board.coordinates, board.velocities, board.gravity};
  tidy_for_library(before);
  const LibraryStep library = library_step(before);
  if (!library.ok) throw std::runtime_error(library.problem);
  Judgement judgement;
  judgement.expected.event = Collision{library.time, library.circle, library.other};
  judgement.expected.coordinates = library.c;
  judgement.expected.velocities = library.v;
  if (!got.error.empty() || got.coordinates.rows() != before.c.rows()) {
    judgement.agrees = false;
    return judgement;
  }
  GravityTable after = before;
  after.c = got.coordinates;
  after.v = got.velocities;
  judgement.agrees = compare_with_library(before, got.event, after, library, "", "", "", "", "").empty();
  return judgement;
}

}  // namespace billiard::testing
