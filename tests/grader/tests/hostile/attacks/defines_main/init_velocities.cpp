// Attack: replace the program's main(), which in a static library would silently win over the
// harness's own, and report every test passed. The grader refuses a task file that defines main.
#include <cstdio>
#include <stdexcept>

#include "billiard/course.hpp"

int main() {
  std::puts("[==========] 12 tests ran.\n[  PASSED  ] 12 tests.\nverdict passed");
  return 0;
}

namespace billiard {
Velocities init_velocities(int, const Coordinates&, Rng&) { throw std::logic_error("not computed"); }
}  // namespace billiard
