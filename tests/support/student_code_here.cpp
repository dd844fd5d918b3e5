// The student's code in the suite's own process (see student_code.hpp): the course's functions
// are linked in, and a program task's program is started from here. Compiled into each suite of
// a program task with BILLIARD_PROGRAM_UNDER_TEST, the program the build made from the task file.
#include "support/student_code.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace billiard::testing {

namespace fs = std::filesystem;

void use_worker(int, int) {
  throw std::logic_error("this suite runs the student's code in its own process; only the grader's judge uses workers");
}

#ifdef BILLIARD_PROGRAM_UNDER_TEST
cli::Run run_student_program(const std::vector<std::string>& arguments,
                             const std::vector<std::pair<std::string, std::string>>& inputs,
                             const cli::Limits& limits) {
  static int runs = 0;
  const fs::path base = fs::temp_directory_path() / ("billiard-program-" + std::to_string(::getpid()) + "-" +
                                                     std::to_string(++runs));
  const fs::path folder = base / "run";
  fs::create_directories(folder);
  for (const auto& [name, content] : inputs) std::ofstream(folder / name, std::ios::binary) << content;
  const cli::Run run = cli::run_program(BILLIARD_PROGRAM_UNDER_TEST, arguments, folder, base / "output", limits);
  std::error_code ignored;
  fs::remove_all(base, ignored);
  return run;
}
#endif

}  // namespace billiard::testing
