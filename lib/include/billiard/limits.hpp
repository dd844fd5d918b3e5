// The numbers billiard accepts, in one place for the course functions, the engine and the
// commands. They square and multiply lengths, speeds and masses (times of impact, impulses,
// overlaps): beyond these magnitudes the products overflow or underflow and the results turn to
// garbage or nan, so every check, and the words of its message, come from here.
#pragma once

#include <cmath>

namespace billiard::limits {

inline constexpr double kLargest = 1e50;    // coordinates, lengths, speeds, accelerations, spins, times
inline constexpr double kSmallest = 1e-50;  // radii, masses and moments of inertia are at least this

// The rules as a message states them, after the value's name.
inline constexpr const char* kMustBeBounded = "must be finite and at most 1e50 in magnitude";
inline constexpr const char* kMustBeInScale = "must be positive and finite, in [1e-50, 1e50]";

// Whether x obeys the rule; both are false for nan and the infinities.
inline bool bounded(double x) { return std::abs(x) <= kLargest; }
inline bool in_scale(double x) { return x >= kSmallest && x <= kLargest; }
// A point or a velocity: both coordinates bounded.
inline bool bounded(double x, double y) { return bounded(x) && bounded(y); }

// Positions are computed to about 1e-16 of the coordinates: a disc smaller than this fraction of
// the coordinates it moves among would overlap discs and cross walls by rounding alone.
inline constexpr double kRelativeRadius = 1e-6;

}  // namespace billiard::limits
