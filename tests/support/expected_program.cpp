// Compiled into each suite executable of a program task with BILLIARD_EXPECTED_PROGRAM set.
#include "support/expected_program.hpp"

#include <cstdlib>

namespace billiard::testing {

std::string expected_program() {
  const char* value = std::getenv("BILLIARD_EXPECTED_PROGRAM");
  return value != nullptr && *value != '\0' ? value : BILLIARD_EXPECTED_PROGRAM;
}

}  // namespace billiard::testing
