// Helpers shared by the graded suite of task 8 (walls) and its hidden tests: tables with walls,
// random wall layouts with circles placed clear of them, messages naming walls, geometry
// computed independently of the student's code, and one step of the finished library
// (billiard::Simulation) from a shared state, to compare the student's step with.
#pragma once

#include "billiard/engine/simulation.hpp"
#include "billiard/extensions.hpp"
#include "support/failure_pictures.hpp"
#include "support/fixtures.hpp"
#include "support/step_difference.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace billiard::testing {

// A table with its circles and walls.
struct WallTable {
  double R = 10;
  double a = 1;
  Coordinates c;
  Velocities v;
  std::vector<Wall> walls;
  std::string label;
  int n() const { return static_cast<int>(c.rows()); }
};

inline Wall wall(double ax, double ay, double bx, double by) { return Wall{Vector(ax, ay), Vector(bx, by)}; }

// "other = wall_id(2) (circle 0 hits walls[2])" and the like.
inline std::string describe_walls_collision(const Collision& c, int wall_count) {
  std::string other;
  if (c.other == kWall) {
    other = text("other = kWall} (circle ", c.circle, " hits the table's rim");
  } else if (c.other >= 0) {
    other = text("other = ", c.other, "} (circles ", c.circle, " and ", c.other, " collide");
  } else {
    const int k = -2 - c.other;
    other = k < wall_count ? text("other = wall_id(", k, ") = ", c.other, "} (circle ", c.circle, " hits walls[", k, "]")
                           : text("other = ", c.other, "} (no wall has this id: there are ", wall_count, " walls");
  }
  return text("Collision{time = ", c.time, ", circle = ", c.circle, ", ", other, " after time ", c.time, ")");
}

// Distance from p to the segment of `w`, written here independently of the library.
inline double segment_distance(const Vector& p, const Wall& w) {
  const Vector ab = w.b - w.a;
  const double length2 = ab.squaredNorm();
  double s = length2 > 0 ? (p - w.a).dot(ab) / length2 : 0.0;
  s = std::min(1.0, std::max(0.0, s));
  return (p - (w.a + s * ab)).norm();
}

// Signed side of p relative to the line through w (positive on the left of a -> b).
inline double side_of(const Vector& p, const Wall& w) {
  const Vector ab = w.b - w.a;
  const Vector ap = p - w.a;
  return ab(0) * ap(1) - ab(1) * ap(0);
}

// Up to n circles of radius a placed uniformly where `allowed` holds, inside the table, clear of
// every wall and of each other (random sequential addition). Stops after a fixed budget, so the
// result may have fewer rows; callers choose layouts with plenty of room.
inline Coordinates place_circles(double R, double a, int n, const std::vector<Wall>& walls, std::uint64_t seed,
                                 const std::function<bool(const Vector&)>& allowed = nullptr) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vector> placed;
  const double reach = R - a;
  for (int attempt = 0; attempt < 200000 && static_cast<int>(placed.size()) < n; ++attempt) {
    const Vector p(reach * unit(rng), reach * unit(rng));
    if (p.norm() > reach) continue;
    if (allowed && !allowed(p)) continue;
    bool clear = true;
    // A small margin keeps the start clearly valid for every implementation's rounding.
    for (const Wall& w : walls) clear = clear && segment_distance(p, w) >= a * (1 + 1e-6);
    for (const Vector& q : placed) clear = clear && (p - q).norm() >= 2 * a * (1 + 1e-6);
    if (clear) placed.push_back(p);
  }
  Coordinates c(static_cast<Eigen::Index>(placed.size()), 2);
  for (std::size_t i = 0; i < placed.size(); ++i) c.row(static_cast<Eigen::Index>(i)) = placed[i];
  return c;
}

inline constexpr double kPi = 3.14159265358979323846;

inline Vector on_rim(double R, double angle) { return Vector(R * std::cos(angle), R * std::sin(angle)); }

// Random tables with walls. Layout by k % 5: scattered segments; a chord across the whole table
// plus segments; a chain of walls sharing end points; two walls crossing each other (an X) and a
// wall from the rim; a V whose arms meet at a point. Radii, sizes and speeds vary with k.
inline WallTable random_wall_table(int k, std::uint64_t salt) {
  std::mt19937_64 rng(0x3a115ULL + static_cast<std::uint64_t>(k) * 104729ULL + salt);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double radii[] = {10.0, 1.0, 37.0, 250.0};
  const double speeds[] = {1.0, 0.02, 30.0};
  WallTable t;
  t.R = radii[k % 4];
  const double R = t.R;
  auto inside = [&](double max_fraction) {
    const double r = R * max_fraction * std::sqrt(unit(rng));
    const double phi = 2 * kPi * unit(rng);
    return Vector(r * std::cos(phi), r * std::sin(phi));
  };
  const int layout = k % 5;
  const char* names[] = {"scattered walls", "a chord across the table and walls", "a chain of walls",
                         "crossing walls and a wall from the rim", "a V of walls"};
  if (layout == 0) {
    const int count = 1 + k % 4;
    for (int w = 0; w < count; ++w) t.walls.push_back(Wall{inside(0.9), inside(0.9)});
  } else if (layout == 1) {
    const double phi = 2 * kPi * unit(rng);
    t.walls.push_back(Wall{on_rim(R, phi), on_rim(R, phi + 1.5 + 1.5 * unit(rng))});
    t.walls.push_back(Wall{inside(0.8), inside(0.8)});
  } else if (layout == 2) {
    Vector p = inside(0.7);
    for (int w = 0; w < 3; ++w) {
      const Vector q = inside(0.8);
      t.walls.push_back(Wall{p, q});
      p = q;
    }
  } else if (layout == 3) {
    const Vector centre = inside(0.3);
    const double phi = kPi * unit(rng);
    const double half = 0.4 * R;
    t.walls.push_back(Wall{centre - half * Vector(std::cos(phi), std::sin(phi)),
                           centre + half * Vector(std::cos(phi), std::sin(phi))});
    t.walls.push_back(Wall{centre - half * Vector(-std::sin(phi + 0.3), std::cos(phi + 0.3)),
                           centre + half * Vector(-std::sin(phi + 0.3), std::cos(phi + 0.3))});
    const double psi = 2 * kPi * unit(rng);
    t.walls.push_back(Wall{on_rim(R, psi), on_rim(0.5 * R, psi + 0.2)});
  } else {
    const Vector tip = inside(0.4);
    const double phi = 2 * kPi * unit(rng);
    const double opening = 0.3 + 1.2 * unit(rng);
    t.walls.push_back(Wall{tip, tip + 0.5 * R * Vector(std::cos(phi), std::sin(phi))});
    t.walls.push_back(Wall{tip + 0.5 * R * Vector(std::cos(phi + opening), std::sin(phi + opening)), tip});
  }
  const int n = 1 + (k * 7) % 20;
  const double fraction = 0.02 + 0.18 * unit(rng);
  t.a = std::min(R * std::sqrt(fraction / n), 0.2 * R);
  t.c = place_circles(R, t.a, n, t.walls, 300 + static_cast<std::uint64_t>(k) + salt);
  t.v = gaussian_velocities(t.n(), 400 + static_cast<std::uint64_t>(k) + salt) * speeds[k % 3];
  if (k % 6 == 0 && t.n() > 1) {
    for (int i = 0; i < t.n(); i += 2) t.v.row(i).setZero();  // some circles at rest
  }
  t.label = text("random table ", k, " (", names[layout], ", R = ", R, ", a = ", t.a, ", n = ", t.n(), ", ",
                 t.walls.size(), " walls)");
  return t;
}

// The finished library on the same table: circular table, one segment per wall (the library adds
// the end points itself, once per point), the circles as discs of radius a, event log on.
inline Simulation library_simulation(const WallTable& t) {
  Container table = circular_table(t.R);
  for (const Wall& w : t.walls) table.add_segment(w.a, w.b);
  Simulation sim(table);
  const Coordinates positions = t.c;
  const Velocities velocities = t.v;
  sim.add_discs(positions, velocities, t.a);
  sim.set_log_events(true);
  return sim;
}

// Whether the library's logged event is the student's `got` (walls[k] for the library's segment
// a-b or for its end point, which walls sharing it all own).
inline bool library_event_is(const Simulation& sim, const EventRecord& e, const std::vector<Wall>& walls,
                             const Collision& got) {
  if (e.kind == EventKind::DiscDisc) {
    return (got.circle == e.disc && got.other == e.other) || (got.circle == e.other && got.other == e.disc);
  }
  if (got.circle != e.disc) return false;
  const WallShape& shape = sim.container().walls()[static_cast<std::size_t>(e.wall)];
  if (shape.kind == WallKind::Circle) return got.other == kWall;
  const int k = -2 - got.other;
  if (got.other > -2 || k >= static_cast<int>(walls.size())) return false;
  const Vector a = walls[static_cast<std::size_t>(k)].a;
  const Vector b = walls[static_cast<std::size_t>(k)].b;
  if (shape.kind == WallKind::Segment) return shape.a == a && shape.b == b;
  return shape.a == a || shape.a == b;
}

// "circle 3 with walls[1]" for a logged library event (a point names the first wall owning it).
inline std::string describe_library_event(const Simulation& sim, const EventRecord& e, const std::vector<Wall>& walls) {
  if (e.kind == EventKind::DiscDisc) return text("circles ", e.disc, " and ", e.other);
  const WallShape& shape = sim.container().walls()[static_cast<std::size_t>(e.wall)];
  if (shape.kind == WallKind::Circle) return text("circle ", e.disc, " with the table's rim (other = kWall)");
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const Vector a = walls[k].a;
    const Vector b = walls[k].b;
    if (shape.kind == WallKind::Segment && shape.a == a && shape.b == b) {
      return text("circle ", e.disc, " with a face of walls[", k, "] (other = wall_id(", k, ") = ", wall_id(static_cast<int>(k)), ")");
    }
    if (shape.kind == WallKind::Point && (shape.a == a || shape.a == b)) {
      return text("circle ", e.disc, " with the end point (", shape.a.x(), ", ", shape.a.y(), ") of walls[", k,
                  "] (other = wall_id(", k, ") = ", wall_id(static_cast<int>(k)), ")");
    }
  }
  return text("circle ", e.disc, " with a wall");
}

// The student's propagate_walls, recorded for the pictures of a failing case.
inline Collision recorded_walls_step(double R, double a, int n, Coordinates& c, Velocities& v,
                                     const std::vector<Wall>& walls) {
  return recorded_step(table_board(R, a, walls), c, v, [&] { return propagate_walls(R, a, n, c, v, walls); });
}

// Collision::other for a logged library event: kWall, the other circle, or wall_id(k) of the
// first wall owning the segment or end point.
inline int library_other(const Simulation& sim, const EventRecord& e, const std::vector<Wall>& walls) {
  if (e.kind == EventKind::DiscDisc) return e.other;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const Collision candidate{0, e.disc, wall_id(static_cast<int>(k))};
    if (library_event_is(sim, e, walls, candidate)) return candidate.other;
  }
  return kWall;
}

// A student's propagate_walls step (its event `got` and the state c, v it left) against the
// library's from the same state (the logged `event`, `expected_time` after the start, the state
// `after`): whether it names the library's event, whether another event it names comes within
// 1e-9 of the time scale (a tie: rounding decides the order, either is right), and how its step
// differs from the library's.
struct WallStepComparison {
  bool same_event = false;
  bool tie = false;
  StepDifference difference;
  bool agrees() const { return same_event ? difference.none() : tie; }
};

inline WallStepComparison compare_with_library_step(const Simulation& sim, const EventRecord& event, double expected_time,
                                                    const State& after, const WallTable& t, const Collision& got,
                                                    const Coordinates& c, const Velocities& v, double speed) {
  const double scale = t.R / speed;
  WallStepComparison comparison;
  comparison.same_event = library_event_is(sim, event, t.walls, got);
  if (!comparison.same_event) {
    comparison.tie = std::abs(got.time - expected_time) <= 1e-9 * scale;
    return comparison;
  }
  comparison.difference = step_difference(got.time, c, v, expected_time, after.positions, after.velocities,
                                          StepTolerances::of_step(t.R, speed, scale, expected_time));
  return comparison;
}

// The judge of the pictures of a failing case (failure_pictures.hpp): the library's step from
// the board, compared as matches_library compares.
inline Judgement walls_judgement(const Board& board, const Outcome& got) {
  WallTable t;
  t.R = board.table_radius;
  t.a = board.circle_radius;
  t.c = board.coordinates;
  t.v = board.velocities;
  t.walls = board.walls;
  const double speed = std::sqrt(t.v.squaredNorm());
  if (!(speed > 0)) throw std::runtime_error("every circle at rest");
  Simulation sim = library_simulation(t);
  const double start = sim.current_state().time;
  sim.advance(1);
  if (sim.event_log().empty()) throw std::runtime_error("the library found no event");
  const EventRecord& event = sim.event_log().back();
  const State after = sim.current_state();
  Judgement judgement;
  judgement.expected.event = Collision{event.time - start, event.disc, library_other(sim, event, t.walls)};
  judgement.expected.coordinates = after.positions;
  judgement.expected.velocities = after.velocities;
  judgement.agrees = got.error.empty() && compare_with_library_step(sim, event, event.time - start, after, t, got.event,
                                                                    got.coordinates, got.velocities, speed)
                                              .agrees();
  return judgement;
}

// Steps the student's propagate_walls against the library from the library's own states: at
// each step both start from the same state, the library's trajectory goes on. Events within
// 1e-9 of the time scale of each other are a tie (rounding decides their order), and then
// either may come first: such a step is accepted and the library's state taken. Tolerances:
// one step's rounding is ~1e-15 relative; 1e-9 of R (positions), of the root sum of squared
// speeds (velocities) and of the time scale R / that speed (times) is far below any mistake.
// `hint_for` gives the hint for a failure of the given kind ("event", "time", "position",
// "velocity"). Returns false after reporting the first difference.
inline bool matches_library(WallTable t, int steps,
                            const std::function<std::string(const std::string& what, bool wall)>& hint_for) {
  Simulation sim = library_simulation(t);
  const double speed = std::sqrt(t.v.squaredNorm());
  if (!(speed > 0)) return true;
  const int wall_count = static_cast<int>(t.walls.size());
  for (int e = 0; e < steps; ++e) {
    const State before = sim.current_state();
    Coordinates c = before.positions;
    Velocities v = before.velocities;
    const Coordinates start = c;
    const Velocities start_v = v;
    Collision got{};
    const std::string where = text(t.label, ", step ", e);
    try {
      got = recorded_walls_step(t.R, t.a, t.n(), c, v, t.walls);
    } catch (const std::invalid_argument& error) {
      ADD_FAILURE() << explain(text("propagate_walls to accept a valid state (", where, ")"),
                               text("it threw std::invalid_argument: \"", error.what(), "\""),
                               "after a bounce a circle touches the wall up to rounding (1e-15); input checks "
                               "(checks::placement, checks::clear_of_walls) already allow for that, and an earliest "
                               "event always exists while a circle moves.");
      return false;
    }
    sim.advance(1);
    const EventRecord& event = sim.event_log().back();
    const double expected_time = event.time - before.time;
    const State after = sim.current_state();
    const bool wall_event = event.kind == EventKind::DiscWall;
    const WallStepComparison comparison = compare_with_library_step(sim, event, expected_time, after, t, got, c, v, speed);
    if (comparison.agrees()) continue;
    const int i = comparison.difference.circle;
    if (!comparison.same_event) {
      ADD_FAILURE() << explain(text("at ", where, ": the earliest event, ", describe_library_event(sim, event, t.walls),
                                    " after time ", expected_time),
                               text("returned ", describe_walls_collision(got, wall_count)), hint_for("event", wall_event));
    } else if (comparison.difference.what == StepDifference::What::Time) {
      ADD_FAILURE() << explain(text("at ", where, ": ", describe_library_event(sim, event, t.walls), " after time ",
                                    expected_time),
                               text("returned ", describe_walls_collision(got, wall_count)), hint_for("time", wall_event));
    } else if (i < 0) {
      ADD_FAILURE() << explain(text("at ", where, ": coordinates and velocities to keep their ", t.n(), " rows"),
                               text("they have ", c.rows(), " and ", v.rows(), " rows"),
                               "propagate_walls moves the circles and changes velocities; it never adds or removes rows.");
    } else if (comparison.difference.what == StepDifference::What::Position) {
      ADD_FAILURE() << explain(text("at ", where, ": circle ", i, " at ", row(after.positions, i), " after ",
                                    describe_library_event(sim, event, t.walls)),
                               text("it is at ", row(c, i), " (started at ", row(start, i), ", velocity ",
                                    row(start_v, i), ")"),
                               hint_for("position", wall_event));
    } else {
      ADD_FAILURE() << explain(text("at ", where, ": circle ", i, " to have velocity ", row(after.velocities, i),
                                    " after ", describe_library_event(sim, event, t.walls)),
                               text("its velocity is ", row(v, i), " (before the step ", row(start_v, i), ")"),
                               hint_for("velocity", wall_event));
    }
    return false;
  }
  return true;
}

}  // namespace billiard::testing
