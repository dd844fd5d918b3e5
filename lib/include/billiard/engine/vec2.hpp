// Two-dimensional vectors and the "no event" time shared by the whole engine.
// Public API: include the headers in billiard/, never the internals in lib/src/engine/.
#pragma once

#include <Eigen/Core>

#include <limits>

namespace billiard {

// A point or a velocity in the plane. Lengths in the user's units (for example disc radii),
// times in the units the velocities imply.
using Vec2 = Eigen::Vector2d;

// N by 2 list of points or velocities, row i = disc i, column 0 = x, column 1 = y. Row-major,
// so that the memory is laid out like a C-contiguous numpy array of shape (N, 2).
using Points = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

// "Never": the time of impact of two objects that will not meet.
inline constexpr double kNever = std::numeric_limits<double>::infinity();

// z component of the 3D cross product of (a, 0) and (b, 0): the 2D "cross product".
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// a turned by +90 degrees: the velocity of the point at offset a of a body spinning with
// angular velocity 1 is perp(a).
inline Vec2 perp(const Vec2& a) { return Vec2(-a.y(), a.x()); }

}  // namespace billiard
