// Argument checks for the course functions, shared by tasks/ and solutions/. Each throws
// std::invalid_argument with a message that names the argument, its value and what is allowed,
// e.g. "circle_radius = -1: must be a positive, finite number".
#pragma once

#include "billiard/course.hpp"
#include "billiard/extensions.hpp"

#include <string_view>

namespace billiard::checks {

// table_radius and circle_radius positive and finite, in [1e-50, 1e50], n >= 0, and
// circle_radius < table_radius when there is at least one circle.
void table(double table_radius, double circle_radius, int n);

// n >= 0.
void count(int n);

// `rows` has n rows and only finite numbers of magnitude at most 1e50; `name` is the argument's
// name for the message.
void rows(const Eigen::Matrix<double, Eigen::Dynamic, 2>& rows, int n, std::string_view name);

// Every centre inside the table (|r| <= table_radius - circle_radius) and no two circles
// overlapping, both up to a rounding tolerance of 1e-9 table_radius; the first failure in row
// order is the one reported. O(n) for circles that do not overlap (each compared with its neighbours).
void placement(double table_radius, double circle_radius, const Coordinates& coordinates);

// The extension stages (extensions.hpp).

// Both components finite and at most 1e50 in magnitude; `name` is the argument's name.
void vector(const Vector& value, std::string_view name);

// Every wall's end points finite and inside the table (|a|, |b| <= table_radius, up to 1e-9
// table_radius). A wall whose ends coincide is a point: allowed.
void walls(double table_radius, const std::vector<Wall>& walls);

// No circle overlaps a wall: each centre at least circle_radius (less 1e-9 table_radius) from
// every segment. O(n walls).
void clear_of_walls(double table_radius, double circle_radius, const Coordinates& coordinates,
                    const std::vector<Wall>& walls);

// cell_size finite and at least 2 circle_radius (a circle then touches only circles in its own
// and the eight neighbouring cells), and at most kMaxCellsAcross cells across the table
// (2 table_radius / cell_size), so that a grid of cells fits in memory.
inline constexpr double kMaxCellsAcross = 4096;
void cell_size(double table_radius, double circle_radius, double cell_size);

// Distance from the point p to the segment from a to b.
double distance_to_wall(const Vector& p, const Wall& wall);

}  // namespace billiard::checks
