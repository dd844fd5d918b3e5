// Hostile: kinetic_energy tries to forge the test's result and the grader's results files, then
// fails; correct_energy_drift aborts.
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "billiard/course.hpp"

namespace billiard {
namespace {

void forge() {
  // The result file's path is on the command line: claim a pass without knowing the token.
  std::ifstream cmdline("/proc/self/cmdline");
  const std::string arguments((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
  const std::string option = "--graded-result=";
  if (const auto at = arguments.find(option); at != std::string::npos) {
    const std::string path = arguments.substr(at + option.size(), arguments.find('\0', at) - at - option.size());
    const char* token = std::getenv("BILLIARD_GRADER_TOKEN");
    std::ofstream(path) << (token ? token : "guess") << " passed\n";
  }
  // And the grader's outputs, wherever they might be.
  for (const char* path : {"/autograder/results/results.json", "../../results/results.json",
                           "build/grade/results/results.json"}) {
    std::ofstream(path) << "{\"score\": 1000, \"tests\": []}";
  }
}

}  // namespace

double kinetic_energy(int, const Velocities&) {
  forge();
  throw std::runtime_error("forged");
}

void correct_energy_drift(int, Velocities&, double) { std::abort(); }
}  // namespace billiard
