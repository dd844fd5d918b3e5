// The questions the simulation's checks, the event loop, validation and replay ask of a
// container's geometry: where a periodic position wraps to, the nearest periodic image, whether
// a disc is inside, how far it is from a wall, and which region the discs can reach. Each answer
// is written once, here (container.cpp). Internal: not installed.
#pragma once

#include "billiard/engine/container.hpp"
#include "billiard/engine/plane.hpp"
#include "billiard/engine/wall.hpp"

#include <cmath>
#include <optional>
#include <string>

namespace billiard {

// p moved by whole periods into [0, period.x) x [0, period.y); p itself when period is (0, 0)
// (no periodic box).
Vector wrap_into_period(Vector p, const Vector& period);

// p wrapped into the container's periodic box (p itself without one).
inline Vector wrap(const Container& container, const Vector& p) {
  return container.periodic() ? wrap_into_period(p, container.period()) : p;
}

// The shortest of the vectors equal to dr up to whole periods (dr itself without a period).
// (Inline: the event loop calls it at every collision.)
inline Vector minimum_image(const Container& container, Vector dr) {
  if (container.periodic()) {
    const Vector& period = container.period();
    dr.x() -= period.x() * std::round(dr.x() / period.x());
    dr.y() -= period.y() * std::round(dr.y() / period.y());
  }
  return dr;
}

// Whether a disc of `radius` centred at p is inside the container up to `slack`, and if not, what
// it is outside of (no text: placing discs at random tries many places outside).
enum class Outside { No, Table, PeriodicBox, Walls };
Outside where_outside(const Container& container, const Vector& p, double radius, double slack);
// The same as the end of a sentence after "disc i"; "" if it is inside.
std::string outside(const Container& container, const Vector& p, double radius, double slack);

// Gap between a disc of `radius` at p and a wall: the distance from the disc's edge to the wall,
// negative when they overlap. For the circle of a table the disc is inside it.
double wall_clearance(const WallShape& wall, const Vector& p, double radius);

// The first wall (from index `first` of `indices`, or of all walls when indices is null) that a
// disc of `radius` at p overlaps by more than `slack`, with its clearance.
struct WallOverlap {
  int wall;
  double clearance;
};
std::optional<WallOverlap> overlapped_wall(const Container& container, const Vector& p, double radius, double slack,
                                           const int* indices = nullptr, int count = -1);

// A box holding every place a centre can reach: the period, or the box of the table and the
// outlines.
void bounds(const Container& container, Vector& lower, Vector& upper);

// The largest coordinate of the container and the walls. Every wall counts: the distance to a
// segment that reaches into the table from 1e50 away is computed from its far end point.
double extent(const Container& container);

}  // namespace billiard
