// Attack: replace functions of the C library that the grader's processes call, so that every
// process the test server waits for seems to end well and every message seems sent. The grader
// refuses a task file that defines a function of the C library.
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>

#include <cstring>
#include <stdexcept>

#include "billiard/course.hpp"

extern "C" pid_t wait4(pid_t pid, int* status, int, struct rusage* usage) {
  if (status != nullptr) *status = 0;
  if (usage != nullptr) std::memset(usage, 0, sizeof *usage);
  return pid;
}

extern "C" ssize_t send(int, const void*, std::size_t size, int) { return static_cast<ssize_t>(size); }

namespace billiard {
void movie(double, double, int, Coordinates&, Velocities&, int, const std::filesystem::path&) {
  throw std::logic_error("not computed");
}
}  // namespace billiard
