// Compiled into each suite executable of a program task on its own, with
// BILLIARD_PROGRAM_UNDER_TEST and BILLIARD_EXPECTED_PROGRAM set for that executable (the same
// test code runs the reference solution, the stub or a submission).
#include "support/program_under_test.hpp"

#include <cstdlib>

namespace billiard::testing {
namespace {

std::string from_environment(const char* name, const char* built) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : built;
}

}  // namespace

std::string program_under_test() { return from_environment("BILLIARD_PROGRAM_UNDER_TEST", BILLIARD_PROGRAM_UNDER_TEST); }

std::string expected_program() { return from_environment("BILLIARD_EXPECTED_PROGRAM", BILLIARD_EXPECTED_PROGRAM); }

}  // namespace billiard::testing
