// The plane as the engine computes in it: the shared vectors (billiard/vectors.hpp), the "no
// event" time and the 2D cross product.
// Public API: include the headers in billiard/, never the internals in lib/src/engine/.
#pragma once

#include "billiard/vectors.hpp"

#include <limits>

namespace billiard {

// "Never": the time of impact of two objects that will not meet.
inline constexpr double kNever = std::numeric_limits<double>::infinity();

// z component of the 3D cross product of (a, 0) and (b, 0): the 2D "cross product".
inline double cross(const Vector& a, const Vector& b) { return a.x() * b.y() - a.y() * b.x(); }

// a turned by +90 degrees: the velocity of the point at offset a of a body spinning with
// angular velocity 1 is perp(a).
inline Vector perp(const Vector& a) { return Vector(-a.y(), a.x()); }

}  // namespace billiard
