// The program that computes a program task's expected output: the library's own command of the
// task's name (such as `particles`). The suite runs it itself, in its own folder; the path the
// build knows, unless the grader, which runs the suites from a copy outside the build, names
// the copy in the environment (BILLIARD_EXPECTED_PROGRAM).
#pragma once

#include <string>

namespace billiard::testing {

std::string expected_program();

}  // namespace billiard::testing
