// Hostile: an endless loop.
#include "billiard/course.hpp"

namespace billiard {
Collision propagate(double, double, int, Coordinates& coordinates, Velocities&) {
  volatile double spin = 0;
  for (;;) spin = spin + coordinates.size();
}
}  // namespace billiard
