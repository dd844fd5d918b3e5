// The worker of a program task (the C track): answers the judge's runs of the student's program
// (proxy.cpp, run_student_program) on descriptors 3 (in) and 4 (out), one at a time, until the judge closes them.
//
//   program_runner PROGRAM
//
// Each run gets a new folder that holds only the run's input files, so the program never sees
// what its output is compared with (the judge computes that in its own folder); it may not start
// processes of its own. Runs in a cell (tests/grader/cell/cell.c) with the program beside it.
#include "cell_rules.h"
#include "cli/cli_runner.hpp"
#include "judge/endings.hpp"
#include "judge/wire.hpp"

#include <fcntl.h>
#include <sys/prctl.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace {

namespace fs = std::filesystem;
using billiard::judge::Call;
using billiard::judge::Ending;
using billiard::judge::ProgramResult;
using billiard::judge::ProgramRun;
using billiard::judge::Reader;
using billiard::judge::Writer;

// The pipes from and to the judge.
constexpr int kFromJudge = 3, kToJudge = 4;
constexpr std::size_t kOutputBytes = 1u << 20;  // of each stream, sent back per run

void forbid_new_processes() {
  if (cell_forbid_new_processes() != 0) _exit(126);
}

// A file name of the run's folder: the judge's own where it is a plain name.
std::string plain(const std::string& name) {
  const std::string base = fs::path(name).filename().string();
  return base.empty() || base == "." || base == ".." ? std::string("input") : base;
}

ProgramResult run(const std::string& program, const ProgramRun& request, int number) {
  const fs::path folder = "run-" + std::to_string(number);
  fs::create_directory(folder);
  for (const auto& [name, content] : request.inputs) std::ofstream(folder / plain(name), std::ios::binary) << content;
  cli::Limits limits;
  limits.seconds = request.seconds;
  limits.in_child = forbid_new_processes;
  const cli::Run done = cli::run_program(program, request.arguments, folder, "output-" + std::to_string(number), limits);
  ProgramResult result;
  result.status = done.status;
  result.signal = done.signal;
  result.timed_out = done.timed_out;
  result.seconds = done.seconds;
  result.out = done.out.substr(0, kOutputBytes);
  result.err = done.err.substr(0, kOutputBytes);
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  ::prctl(PR_SET_DUMPABLE, 0, 0, 0, 0);
  if (argc != 2) {
    std::fprintf(stderr, "usage: program_runner PROGRAM\n");
    return 2;
  }
  const std::string program = fs::absolute(argv[1]).string();
  for (const int fd : {kFromJudge, kToJudge}) ::fcntl(fd, F_SETFD, FD_CLOEXEC);  // the program never sees them
  for (int number = 1;; ++number) {
    std::string message;
    try {
      message = billiard::judge::receive(kFromJudge);
    } catch (const billiard::judge::ProtocolError&) {
      return 0;  // the judge is done with this test
    }
    Reader request(std::move(message));
    Writer reply;
    try {
      if (request.get<Call>() != Call::run_program) throw std::logic_error("this worker runs a program, nothing else");
      const auto asked = request.get<ProgramRun>();
      const ProgramResult result = run(program, asked, number);
      reply << Ending::returned << result;
    } catch (...) {
      billiard::judge::write_current_exception(reply);
    }
    billiard::judge::send(kToJudge, reply.bytes());
  }
}
