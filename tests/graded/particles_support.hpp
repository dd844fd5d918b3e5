// The particles task (the C track) is graded by output: each test writes one input file, runs
// the student's program `particles FILE END_TIME` on it, and compares what it prints with the
// output of the project's own `particles` command on the same file (the engine: nothing is
// hard-coded). Positions must agree within 1e-6, the collision counts exactly, and every line
// must have the assignment's format, printf("%.6f, %.6f, %d, %d\n").
#pragma once

#include "cli/cli_runner.hpp"
#include "support/expected_program.hpp"
#include "support/student_code.hpp"
#include "support/student_messages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace particles_grading {

namespace fs = std::filesystem;
using billiard::testing::explain;
using billiard::testing::text;

// A student's program gets this long per file (the largest test file takes milliseconds). Under
// the grader, which names its own limit per test in BILLIARD_TEST_TIME_LIMIT, that limit applies
// instead, as for every other task: a program that hangs is a test that did not finish.
inline double seconds_per_run() {
  const char* grader_limit = std::getenv("BILLIARD_TEST_TIME_LIMIT");
  return grader_limit != nullptr ? std::atof(grader_limit) + 60 : 10;
}
constexpr double kPositionTolerance = 1e-6;
constexpr const char* kFormatHint =
    "print each particle with printf(\"%.6f, %.6f, %d, %d\\n\", x, y, wall_collisions, particle_collisions), "
    "one line per particle in the file's order, and nothing else on stdout";
constexpr const char* kAdvanceHint =
    "the collision counts are right but the positions are not: after the last collision up to END_TIME, "
    "advance every particle to END_TIME (x += u (END_TIME - t), y += v (END_TIME - t))";

struct Line {
  double x = 0, y = 0;
  long walls = 0, others = 0;
};

inline std::vector<std::string> lines_of(const std::string& output) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The assignment's format, strictly: "%.6f, %.6f, %d, %d".
inline bool parse_line(const std::string& line, Line& parsed) {
  static const std::regex format(R"(^(-?[0-9]+\.[0-9]{6}), (-?[0-9]+\.[0-9]{6}), ([0-9]+), ([0-9]+)$)");
  std::smatch match;
  if (!std::regex_match(line, match, format)) return false;
  parsed.x = std::stod(match[1]);
  parsed.y = std::stod(match[2]);
  parsed.walls = std::stol(match[3]);
  parsed.others = std::stol(match[4]);
  return true;
}

inline fs::path work_folder() {
  const fs::path folder = fs::temp_directory_path() / ("particles_graded_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  return folder;
}

// Whether a run was stopped for taking too long: by this suite's clock, or by the CPU time limit
// the grader gives each test, which the program inherits (SIGXCPU): an endless loop, not a crash.
inline bool ran_out_of_time(const cli::Run& run) { return run.timed_out || run.signal == SIGXCPU; }

// What went wrong with a run that did not finish normally, in words; empty if it did.
inline std::string run_problem(const cli::Run& run) {
  if (run.timed_out) {
    return text("it did not finish within ", seconds_per_run(), " s and was stopped");
  }
  if (run.signal == SIGXCPU) return "it did not finish within the computing time the test may take and was stopped";
  if (run.signal != 0) return text("it crashed (signal ", run.signal, ", ", strsignal(run.signal), ")");
  if (run.status != 0) {
    std::string err = run.err.substr(0, run.err.find('\n'));
    return text("it exited with status ", run.status, err.empty() ? "" : ", saying \"" + err + "\"");
  }
  return "";
}

// Runs both programs on `input` up to `end_time` and compares. `hint` names the likely mistake
// when this file's collision counts or positions differ; `positions_hint`, if given, replaces it
// when only the positions do.
inline void expect_same_output(const std::string& name, const std::string& input, const std::string& end_time,
                               const std::string& hint, const std::string& positions_hint = "") {
  const fs::path folder = work_folder();
  const fs::path file = folder / (name + ".txt");
  std::ofstream(file, std::ios::binary) << input;
  const std::vector<std::string> arguments{file.filename().string(), end_time};
  const std::string command = "particles " + name + ".txt " + end_time + " with " + name + ".txt:\n" + input;

  const cli::Run expected = cli::run_program(billiard::testing::expected_program(), arguments, folder, folder / "expected");
  ASSERT_EQ(expected.status, 0) << "the project's particles command failed on this test's file: " << expected.err;

  // The program runs in a folder of its own that holds only the input file.
  cli::Limits limits;
  limits.seconds = seconds_per_run();
  const cli::Run run = billiard::testing::run_student_program(arguments, {{file.filename().string(), input}}, limits);
  // The untouched stub says so and exits: that is the "not implemented yet" failure of every test.
  const std::string first_error = run.err.substr(0, run.err.find('\n'));
  if (run.status > 0 && first_error.find("is not implemented yet") != std::string::npos) {
    throw std::logic_error(first_error);
  }
  const std::string problem = run_problem(run);
  if (!problem.empty()) {
    FAIL() << explain(text("the program to finish with exit status 0 on ", command), problem,
                      ran_out_of_time(run) ? "does your loop end once the next collision comes after END_TIME (or never)? "
                                      "A time of INFINITY must stop it too"
                                    : "check array indices (the N(N+1)/2 array, particle numbers) and that the "
                                      "file is read as line 1 N, line 2 R, line 3 Lx Ly, then N lines x y u v");
  }

  const auto want = lines_of(expected.out);
  const auto got = lines_of(run.out);
  if (got.size() != want.size()) {
    FAIL() << explain(text(want.size(), " lines (one per particle) for ", command),
                      text(got.size(), " lines:\n", run.out.substr(0, 2000)), kFormatHint);
  }
  std::vector<Line> wanted(want.size()), gotten(got.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    if (!parse_line(want[k], wanted[k])) FAIL() << "the project's particles command printed \"" << want[k] << "\"";
    if (!parse_line(got[k], gotten[k])) {
      FAIL() << explain(text("line ", k + 1, " like \"", want[k], "\" for ", command),
                        text("line ", k + 1, " is \"", got[k], "\""), kFormatHint);
    }
  }
  for (std::size_t k = 0; k < got.size(); ++k) {
    if (gotten[k].walls != wanted[k].walls || gotten[k].others != wanted[k].others) {
      FAIL() << explain(text("particle ", k, " to end with ", wanted[k].walls, " wall and ", wanted[k].others,
                             " particle collisions (line ", k + 1, ": \"", want[k], "\") for ", command),
                        text(gotten[k].walls, " wall and ", gotten[k].others, " particle collisions (\"", got[k], "\")"),
                        hint);
    }
  }
  for (std::size_t k = 0; k < got.size(); ++k) {
    // The printed digits are rounded: allow the tolerance plus the last digit's rounding.
    if (std::abs(gotten[k].x - wanted[k].x) > kPositionTolerance * 1.001 ||
        std::abs(gotten[k].y - wanted[k].y) > kPositionTolerance * 1.001) {
      FAIL() << explain(text("particle ", k, " at \"", want[k], "\" (within ", kPositionTolerance, ") for ", command),
                        text("\"", got[k], "\""), positions_hint.empty() ? hint : positions_hint);
    }
  }
}

}  // namespace particles_grading
