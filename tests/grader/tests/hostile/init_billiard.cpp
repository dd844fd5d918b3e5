// Hostile: ends the whole test program with status 0 in the middle of a test.
#include <cstdlib>

#include "billiard/course.hpp"

namespace billiard {
Coordinates init_billiard(double, double, int, Rng&) { std::exit(0); }
}  // namespace billiard
