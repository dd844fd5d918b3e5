// The names of points and velocities in the plane, one per meaning, for the course contract and
// the engine alike: a row of a table of discs is a Vector, and what a course function takes or
// returns is what the engine takes or returns.
#pragma once

#include <Eigen/Core>

namespace billiard {

// A point, a velocity or an acceleration in the plane, (x, y): one row of Coordinates.
using Vector = Eigen::RowVector2d;

// n points, one per row: row i is (x, y) of disc i (or of a polygon's vertex i, ...).
using Coordinates = Eigen::Matrix<double, Eigen::Dynamic, 2>;

// n velocities, one per row: row i is (vx, vy) of disc i. The same type as Coordinates.
using Velocities = Coordinates;

}  // namespace billiard
