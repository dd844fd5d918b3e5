// Discs and snapshots of the whole system.
#pragma once

#include "billiard/engine/plane.hpp"
#include "billiard/wall_hit.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

namespace billiard {

// One disc as the user describes it. Units are the user's: lengths (position, radius), speeds,
// masses; inertia in mass x length^2; spin (angular velocity) in radians per time unit,
// counter-clockwise positive.
struct Disc {
  Vector position = Vector::Zero();
  Vector velocity = Vector::Zero();
  double radius = 1.0;                  // > 0
  double mass = 1.0;                    // > 0
  std::optional<double> inertia;        // in (0, mass radius^2] (a thin ring); unset: a uniform
                                        // disc, mass radius^2 / 2
  double spin = 0.0;
};

// The state of all discs at one time. Row i is disc i (the id add_disc returned).
struct State {
  double time = 0.0;
  Coordinates positions;    // N by 2
  Velocities velocities;    // N by 2
  Eigen::VectorXd spins;    // N
};

// What a logged event was: a collision of two discs or of a disc with a wall, or a disc falling
// asleep or waking up (see Settings::sleep_speed).
enum class EventKind : int { DiscDisc, DiscWall, Sleep, Wake };

// One recorded event (the event log). `other` is the second disc, or kNoDisc when there is none:
// a wall hit (`wall` is then the wall's index, see Container::walls()), a disc falling asleep or
// waking up. wall = kNoWall unless a wall was hit. Positions and velocities are those just after
// the event (at `time`); the other_* fields are zero unless `other` is a disc.
inline constexpr int kNoWall = -1;
// (The course's value for the table's wall, wall_hit.hpp: its collisions and this log compare.)
inline constexpr int kNoDisc = kWall;
struct EventRecord {
  double time = 0.0;
  EventKind kind = EventKind::DiscDisc;
  int disc = 0;
  int other = 0;
  int wall = kNoWall;
  Vector position = Vector::Zero();
  Vector velocity = Vector::Zero();
  double spin = 0.0;
  Vector other_position = Vector::Zero();
  Vector other_velocity = Vector::Zero();
  double other_spin = 0.0;
};

}  // namespace billiard
