// Where the student's code runs. A graded suite calls the course's functions as C++ functions
// and runs a program task's program as a program; both happen either in the suite's own process
// (CTest: ./build.sh test, the stub check), or, under the grader, in a worker process in a cell of
// its own, which the suite (the judge) reaches through a socket (tests/grader/judge/). Which one
// is chosen when the suite is linked: with the course's code (student_code_here.cpp) or with the
// proxies that call the worker (tests/grader/judge/proxy.cpp).
#pragma once

#include "cli/cli_runner.hpp"

#include <string>
#include <utility>
#include <vector>

namespace billiard::testing {

// The judge's channels to the running test's worker, a pipe each way (grader only; once per test
// process).
void use_worker(int to_worker, int from_worker);

// Runs a program task's program with `arguments` in a folder that holds only `inputs` (file
// name, content): its output, status and time, as cli::run_program gives them.
cli::Run run_student_program(const std::vector<std::string>& arguments,
                             const std::vector<std::pair<std::string, std::string>>& inputs,
                             const cli::Limits& limits);

}  // namespace billiard::testing
