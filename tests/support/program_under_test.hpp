// The programs a graded suite of a program task (a C task such as particles) runs: the
// student's program, and the library's own command that computes the expected output. Each is
// the path the build knows, unless the grader, which runs the suites from a copy outside the
// build, names the copies in the environment (BILLIARD_PROGRAM_UNDER_TEST,
// BILLIARD_EXPECTED_PROGRAM).
#pragma once

#include <string>

namespace billiard::testing {

std::string program_under_test();
std::string expected_program();

}  // namespace billiard::testing
