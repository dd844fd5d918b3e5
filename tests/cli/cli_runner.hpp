// Running the `billiard` command from a test: no shell in between, so every argument reaches
// the program exactly as given (empty strings, spaces, newlines), with a time limit, and with
// what it printed and left behind available for checks. Shared by the CLI tests and the fuzz test.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace cli {

namespace fs = std::filesystem;

struct Run {
  int status = -1;         // exit status, or -1 if the program did not exit by itself
  int signal = 0;          // the signal that ended it, or 0
  bool timed_out = false;  // killed for running longer than the limit
  double seconds = 0;      // wall-clock time of the run
  std::string out, err;    // what it printed on stdout and stderr
};

inline std::string slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Arguments quoted as for a shell, with newlines and tabs escaped, for messages.
inline std::string shown(const std::vector<std::string>& arguments) {
  std::string line;
  for (const auto& argument : arguments) {
    line += line.empty() ? "'" : " '";
    for (const char c : argument) {
      if (c == '\n') {
        line += "\\n";
      } else if (c == '\t') {
        line += "\\t";
      } else if (c == '\'') {
        line += "'\\''";
      } else {
        line += c;
      }
    }
    line += "'";
  }
  return line;
}

struct Limits {
  double seconds = 60;          // killed (SIGKILL) after this long: a hang is reported, not waited for
  double interrupt_after = -1;  // if >= 0, send `interrupt` this many seconds after the start
  int interrupt = SIGINT;
  void (*in_child)() = nullptr;  // if set, called in the new process just before the program starts
};

// Runs `exe arguments...` with `folder` as the current folder; stdout and stderr go to
// `logs`.out and `logs`.err (outside `folder`, so that they are not counted as its files).
inline Run run_program(const std::string& exe, const std::vector<std::string>& arguments, const fs::path& folder,
                       const fs::path& logs, const Limits& limits = {}) {
  const std::string out_file = logs.string() + ".out", err_file = logs.string() + ".err";
  const std::string folder_name = folder.string();
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(exe.c_str()));
  for (const auto& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
  argv.push_back(nullptr);

  const auto start = std::chrono::steady_clock::now();
  const pid_t child = ::fork();
  if (child == 0) {
    // Only async-signal-safe calls between fork and exec.
    const int out = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || ::chdir(folder_name.c_str()) != 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0) _exit(127);
    ::close(out);
    ::close(err);
    if (limits.in_child != nullptr) limits.in_child();
    ::execv(exe.c_str(), argv.data());
    _exit(127);
  }
  Run run;
  if (child < 0) {
    run.err = std::string("fork failed: ") + std::strerror(errno);
    return run;
  }
  // A watchdog thread sends the interruption, and kills the child at the time limit, unless
  // the child ends first; meanwhile this thread waits for the child without polling.
  std::mutex mutex;
  std::condition_variable ended;
  bool finished = false;
  std::thread watchdog([&] {
    std::unique_lock<std::mutex> lock(mutex);
    const auto at = [&](double seconds) { return start + std::chrono::duration<double>(seconds); };
    if (limits.interrupt_after >= 0 && !ended.wait_until(lock, at(limits.interrupt_after), [&] { return finished; })) {
      ::kill(child, limits.interrupt);
    }
    if (!ended.wait_until(lock, at(limits.seconds), [&] { return finished; })) {
      run.timed_out = true;
      ::kill(child, SIGKILL);
    }
  });
  // Waits for the end without reaping the child, so that its process id stays its own
  // until the watchdog is stopped; then reaps it.
  siginfo_t info{};
  while (::waitid(P_PID, id_t(child), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    finished = true;
  }
  ended.notify_one();
  watchdog.join();
  int raw = 0;
  while (::waitpid(child, &raw, 0) < 0 && errno == EINTR) {
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (WIFEXITED(raw) && !run.timed_out) run.status = WEXITSTATUS(raw);
  if (WIFSIGNALED(raw)) run.signal = WTERMSIG(raw);
  run.out = slurp(out_file);
  run.err = slurp(err_file);
  return run;
}

// Everything under `root`, by relative path: a file's content, "<folder>", or "<link> target".
inline std::map<std::string, std::string> tree(const fs::path& root) {
  std::map<std::string, std::string> entries;
  std::error_code error;
  for (auto entry = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied, error);
       !error && entry != fs::recursive_directory_iterator(); entry.increment(error)) {
    const std::string name = entry->path().lexically_relative(root).string();
    if (entry->is_symlink()) {
      entries[name] = "<link> " + fs::read_symlink(entry->path()).string();
    } else if (entry->is_directory()) {
      entries[name] = "<folder>";
    } else {
      entries[name] = slurp(entry->path());
    }
  }
  return entries;
}

// What is wrong with a run that should have been refused as bad input (exit status 2, exactly
// one line on stderr starting "billiard: ", nothing on stdout); empty if nothing is.
inline std::string refusal_problems(const Run& run) {
  std::string problems;
  if (run.status != 2) problems += "exit status " + std::to_string(run.status) + ", expected 2; ";
  const auto lines = std::count(run.err.begin(), run.err.end(), '\n');
  if (lines != 1 || run.err.empty() || run.err.back() != '\n') problems += "stderr is not exactly one line; ";
  if (run.err.rfind("billiard: ", 0) != 0) problems += "stderr does not start with 'billiard: '; ";
  if (!run.out.empty()) problems += "stdout is not empty; ";
  return problems;
}

}  // namespace cli
