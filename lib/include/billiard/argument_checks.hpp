// Argument checks for the course functions, shared by tasks/ and solutions/. Each throws
// std::invalid_argument with a message that names the argument, its value and what is allowed,
// e.g. "circle_radius = -1: must be a positive, finite number".
#pragma once

#include "billiard/course.hpp"

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
// overlapping, both up to a rounding tolerance of 1e-9 table_radius. O(n^2).
void placement(double table_radius, double circle_radius, const Coordinates& coordinates);

}  // namespace billiard::checks
