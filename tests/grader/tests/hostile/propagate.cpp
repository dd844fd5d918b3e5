// Hostile: an endless loop, after starting a process that leaves the test's process group and
// loops forever too (the grader must stop it when the test is over).
#include <unistd.h>

#include "billiard/course.hpp"

namespace billiard {
Collision propagate(double, double, int, Coordinates& coordinates, Velocities&) {
  if (fork() == 0) setsid();
  volatile double spin = 0;
  for (;;) spin = spin + coordinates.size();
}
}  // namespace billiard
