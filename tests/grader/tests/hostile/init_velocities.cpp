// Hostile: a segmentation fault (writes through a null pointer the compiler cannot see).
#include <cstdlib>

#include "billiard/course.hpp"

namespace billiard {
Velocities init_velocities(int n, const Coordinates&, Rng&) {
  volatile int* nowhere = reinterpret_cast<int*>(std::getenv("BILLIARD_NO_SUCH_VARIABLE"));
  *nowhere = n;
  return Velocities(n, 2);
}
}  // namespace billiard
