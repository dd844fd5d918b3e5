// The extension stages of the course: tasks 7 (gravity), 8 (walls) and 9 (sectors), which
// students write on top of their tasks 1-6 once those pass. Same conventions as course.hpp:
// circles of radius circle_radius on a table of radius table_radius centred at the origin,
// n rows of (x, y), std::invalid_argument naming the argument for bad input. Each stage's
// file in tasks/ explains its job, the formulas and the numerical traps.
#pragma once

#include "billiard/course.hpp"

#include <vector>

namespace billiard {

// A straight wall inside the table: the segment from a to b, both end points included. Circles
// bounce off either side and off the end points.
struct Wall {
  Vector a, b;
};

// Collision::other for a collision with walls[k] (kWall, -1, stays the table).
inline constexpr int wall_id(int k) { return -2 - k; }

// Task 7. Like propagate, with the uniform acceleration g acting on every circle: between
// events each centre moves on the parabola r + v t + g t^2 / 2 and each velocity becomes
// v + g t. Throws std::invalid_argument also if g is not finite or larger than 1e50.
Collision propagate_gravity(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, const Vector& g);

// Task 7. Mean energy per circle (unit mass): (1/n) sum_i (|v_i|^2 / 2 - g . r_i); 0 for n = 0.
double mean_energy(int n, const Coordinates& coordinates, const Velocities& velocities, const Vector& g);

// Task 8. Like propagate, with straight walls inside the table. Collision::other is kWall for
// the table, wall_id(k) for walls[k] (its side or an end point) or the other circle's row.
// Throws std::invalid_argument also for a wall with a non-finite or out-of-table end point, and
// for a circle that starts overlapping a wall.
Collision propagate_walls(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                          Velocities& velocities, const std::vector<Wall>& walls);

// Task 9. Like propagate (no gravity, no walls), but finds the next collision through square
// cells of side cell_size >= 2 circle_radius instead of testing all pairs: returns the same
// collision as propagate would, after moving through any number of cell crossings on the way.
// The cells are built afresh at each call (O(n)); no state survives between calls.
Collision propagate_sectors(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                            Velocities& velocities, double cell_size);

// Provided for task 9 (not written by students): the time until circles i and j touch, moving
// in straight lines, or infinity if they never do (same formula as in propagate). Each call is
// counted, so that the graded suite can measure how many pairs task 9 tests per collision
// without timing anything. Throws std::invalid_argument for rows outside coordinates.
double pair_time(double circle_radius, const Coordinates& coordinates, const Velocities& velocities, int i, int j);

// How many times pair_time has been called since the program started (in this thread).
long long pair_time_calls();

}  // namespace billiard
