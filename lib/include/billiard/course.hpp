// The course contract: the six functions students write for N hard discs ("circles") that
// collide elastically on a circular table of radius `table_radius` centred at the origin.
// Included by tasks/ (the student's code), solutions/ (the reference), tests/ and the CLI.
// Each task's file in tasks/ explains its job and the formulas it needs.
//
// Units: lengths in table units, times in the units the velocities imply (length / speed).
// Arrays: `Coordinates` and `Velocities` (billiard/vectors.hpp, the engine's too) have n rows,
// column 0 is x and column 1 is y; one row is a `Vector`.
// Errors: invalid arguments throw std::invalid_argument whose message names the argument.
// Numbers must be finite and at most 1e50 in magnitude, radii at least 1e-50 (squares of larger
// ones overflow).
#pragma once

#include "billiard/vectors.hpp"
#include "billiard/wall_hit.hpp"

#include <filesystem>
#include <random>

namespace billiard {

using Rng = std::mt19937_64;

struct Collision {
  double time;  // time advanced to reach this collision (>= 0)
  int circle;   // the circle that collided (row index)
  int other;    // the other circle's row index, or kWall for the table wall
};

// Task 1. Random centres for n circles of radius circle_radius, fully inside the table
// (|r_i| <= table_radius - circle_radius) and not overlapping (|r_i - r_j| >= 2 circle_radius).
// Draws all randomness from `rng`, so the same seed gives the same table. Throws
// std::invalid_argument for radii that are not positive and finite, circle_radius >=
// table_radius with n > 0, n < 0, or n circles that cannot be placed (the message says why).
Coordinates init_billiard(double table_radius, double circle_radius, int n, Rng& rng);

// Task 2. Random velocities for the n circles at `coordinates` (n rows): random directions
// with no preferred direction (every angle as likely), not all zero. Throws
// std::invalid_argument if n < 0 or coordinates.rows() != n.
Velocities init_velocities(int n, const Coordinates& coordinates, Rng& rng);

// Task 3. Writes `svg_file`: an SVG picture with the table wall as one <circle> centred at the
// origin with radius table_radius, and each circle as one <circle> with its centre and radius
// (a scale factor and a flipped y axis are allowed). Throws std::invalid_argument for bad
// radii or row counts, std::runtime_error if the file cannot be written.
void visualize_table(double table_radius, double circle_radius, int n,
                     const Coordinates& coordinates, const std::filesystem::path& svg_file);

// Task 4. One event step: finds the earliest future collision (circle with wall or circle with
// circle), moves every circle in a straight line for that time, updates the velocities of the
// colliding circle(s) (ideal reflection at the wall; elastic collision of equal masses between
// circles) and returns that collision. `coordinates` and `velocities` are left at the moment
// just after it. Throws std::invalid_argument if no collision can ever happen (n = 0, or all
// circles at rest), or for bad radii or row counts.
Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates,
                    Velocities& velocities);

// Task 5. Calls propagate `collisions` times and writes `svg_file`: an animated SVG (SMIL
// <animate> of cx and cy, linear between collisions, which is exact for straight-line motion)
// that plays in a browser. Leaves coordinates and velocities advanced by `collisions` events.
// Throws std::invalid_argument for collisions < 0 and whatever propagate throws.
void movie(double table_radius, double circle_radius, int n, Coordinates& coordinates,
           Velocities& velocities, int collisions, const std::filesystem::path& svg_file);

// Task 6. The mean squared velocity <v^2> = (1/n) sum_i |v_i|^2 (0 for n = 0). Throws
// std::invalid_argument if n < 0 or velocities.rows() != n.
double kinetic_energy(int n, const Velocities& velocities);

// Task 6 (continued). Rescales every velocity by the same factor so that the mean squared
// velocity becomes `target_mean_square`, keeping every direction. Throws std::invalid_argument
// if target_mean_square is negative or not finite, or if it is positive while all circles are
// at rest (no factor can help), or for bad n or row counts.
void correct_energy_drift(int n, Velocities& velocities, double target_mean_square);

}  // namespace billiard
